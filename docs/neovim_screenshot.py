"""Render docs/neovim-finding.png: a headless Neovim in a tmux pane, attached to
``ncverify lsp`` on the quick-start program, captured with ``tmux capture-pane -e`` and drawn
to PNG (needs nvim, tmux and Pillow).

    python docs/neovim_screenshot.py
"""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

from PIL import Image, ImageDraw, ImageFont

HERE = Path(__file__).resolve().parent
PROGRAM = HERE.parent / "corpus" / "iso" / "quickstart-bracket.nc"
COLUMNS, ROWS = 110, 30
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf"
BASIC = [(0, 0, 0), (205, 49, 49), (13, 188, 121), (229, 229, 16), (36, 114, 200), (188, 63, 188), (17, 168, 205), (229, 229, 229),
         (102, 102, 102), (241, 76, 76), (35, 209, 139), (245, 245, 67), (59, 142, 234), (214, 112, 214), (41, 184, 219), (255, 255, 255)]
FOREGROUND, BACKGROUND = (220, 220, 220), (24, 24, 24)


def capture() -> str:
    session = f"ncverify-shot-{os.getpid()}"
    env = dict(os.environ, NCVERIFY_SERVER=json.dumps([sys.executable, "-m", "ncverify.cli", "lsp"]), NCVERIFY_LINE="14", TERM="xterm-256color")
    command = f"nvim --clean -u NONE -c 'luafile {HERE / 'neovim_screenshot.lua'}' {PROGRAM}"
    subprocess.run(["tmux", "new-session", "-d", "-s", session, "-x", str(COLUMNS), "-y", str(ROWS), command], env=env, check=True)
    try:
        time.sleep(20)
        return subprocess.run(["tmux", "capture-pane", "-e", "-p", "-t", session], capture_output=True, text=True, check=True).stdout
    finally:
        subprocess.run(["tmux", "kill-session", "-t", session], check=False)


def color(codes: list[int], index: int) -> tuple[tuple[int, int, int], int]:
    """The colour an SGR 38/48 sequence starting at ``index`` names, and the next index."""
    if codes[index + 1] == 5:
        return palette(codes[index + 2]), index + 3
    return tuple(codes[index + 2:index + 5]), index + 5


def palette(number: int) -> tuple[int, int, int]:
    if number < 16:
        return BASIC[number]
    if number < 232:
        number -= 16
        steps = [0, 95, 135, 175, 215, 255]
        return steps[number // 36], steps[(number // 6) % 6], steps[number % 6]
    grey = 8 + (number - 232) * 10
    return grey, grey, grey


def cells(text: str):
    """Yield (row, column, character, foreground, background, bold) for the captured pane."""
    for row, line in enumerate(text.splitlines()[:ROWS]):
        foreground, background, bold, reverse, column = FOREGROUND, BACKGROUND, False, False, 0
        for part in re.split(r"(\x1b\[[0-9;]*m)", line):
            if part.startswith("\x1b["):
                codes = [int(code) if code else 0 for code in part[2:-1].split(";")]
                index = 0
                while index < len(codes):
                    code = codes[index]
                    if code == 0:
                        foreground, background, bold, reverse = FOREGROUND, BACKGROUND, False, False
                    elif code == 1:
                        bold = True
                    elif code == 7:
                        reverse = True
                    elif code in (38, 48):
                        value, index = color(codes, index)
                        foreground, background = (value, background) if code == 38 else (foreground, value)
                        continue
                    elif code == 39:
                        foreground = FOREGROUND
                    elif code == 49:
                        background = BACKGROUND
                    elif 30 <= code <= 37 or 90 <= code <= 97:
                        foreground = BASIC[code - 30 if code < 90 else code - 82]
                    elif 40 <= code <= 47 or 100 <= code <= 107:
                        background = BASIC[code - 40 if code < 100 else code - 92]
                    index += 1
                continue
            for character in part:
                fg, bg = (background, foreground) if reverse else (foreground, background)
                yield row, column, character, fg, bg, bold
                column += 1


def render(text: str, target: Path) -> None:
    font = ImageFont.truetype(FONT, 15)
    width, height = font.getbbox("M")[2], 19
    image = Image.new("RGB", (COLUMNS * width + 16, ROWS * height + 16), BACKGROUND)
    draw = ImageDraw.Draw(image)
    for row, column, character, foreground, background, bold in cells(text):
        x, y = 8 + column * width, 8 + row * height
        draw.rectangle([x, y, x + width, y + height], fill=background)
        draw.text((x, y), character, font=font, fill=foreground, stroke_width=1 if bold else 0, stroke_fill=foreground)
    image.save(target)


if __name__ == "__main__":
    render(capture(), HERE / "neovim-finding.png")
