"""A real editor: Debian's Neovim (0.7), headless, attached to ``ncverify lsp``, opening a
program of each dialect and reading back the diagnostics it shows."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from ncverify import check_file

if not os.environ.get("CI"):  # in CI the test extra installs it: a missing pygls fails there
    pytest.importorskip("pygls", reason="the lsp extra is not installed")

ROOT = Path(__file__).resolve().parent.parent
PROGRAMS = [ROOT / "corpus" / "iso" / "quickstart-bracket.nc", ROOT / "corpus" / "heidenhain" / "pocket.h",
            ROOT / "corpus" / "sinumerik" / "shifted-arguments.mpf", ROOT / "corpus" / "fagor" / "bad-cycle-left-active.pim"]


def _neovim() -> str:
    found = shutil.which("nvim")
    if found is None:
        if os.environ.get("CI"):
            pytest.fail("nvim is missing: .ci/run installs Debian's neovim package")
        pytest.skip("nvim is not installed (apt-get install neovim)")
    return found


def test_neovim_shows_the_findings_of_every_dialect(tmp_path: Path):
    neovim = _neovim()
    out = tmp_path / "diagnostics.json"
    env = dict(os.environ, NCVERIFY_SERVER=json.dumps([sys.executable, "-m", "ncverify.cli", "lsp"]),
               NCVERIFY_FILES="\n".join(str(path) for path in PROGRAMS), NCVERIFY_OUT=str(out))
    subprocess.run([neovim, "--headless", "--clean", "-u", "NONE", "-c", f"luafile {ROOT / 'tests' / 'nvim' / 'read_diagnostics.lua'}"],
                   env=env, cwd=tmp_path, timeout=600, check=True, stdin=subprocess.DEVNULL, capture_output=True)
    shown = json.loads(out.read_text(encoding="utf-8"))
    for path in PROGRAMS:
        expected = {(d.span.line, d.rule) for d in check_file(path).diagnostics if not d.span.path}
        assert expected, path
        assert {(item["line"], item["code"]) for item in shown[str(path)]} == expected, path
        assert all(item["severity"] != 1 for item in shown[str(path)] if item["message"].startswith("unknown:"))
