"""Programs for the oracle (``tests/oracle.py``): Hypothesis strategies that draw a program
tree, and one writer per dialect that turns the tree into program text.

Every dialect gets rapids, feeds and half circles whose coordinates depend on the free
parameter ``p`` (and, inside a loop, on the pass), loops, subprogram calls, a drilling
cycle, tool changes and the coordinate transforms the dialect has: ISO ``G52``, ``G92``
and ``G68`` (read, not modelled: the checker must not prove under it), SINUMERIK frames
(``TRANS``, ``AMIRROR``, ``AROT``, ``ASCALE``), Klartext cycles 7, 8, 10 and 11, Fagor's
``G92`` preset; LinuxCNC as ISO with O-word loops and subprograms.

A writer returns the files (the main program first) and, per file and line, the tags of
the oracle's moves written there (``oracle.run`` gives every move the same tag).
"""
from __future__ import annotations

from hypothesis import strategies as st

from tests.oracle import (Call, Case, Drill, Feed, HalfCircle, Linear, Loop, Mirror, Preset, Rapid, Rotate, Scale, Shift, Tool,
                          ToolChange)

PARAMETER = {"iso": "#1", "linuxcnc": "#100", "sinumerik": "R1", "fagor": "P1", "heidenhain": "Q1"}
COUNTER = {"iso": "#2", "linuxcnc": "#101", "sinumerik": "R2", "fagor": "P2", "heidenhain": "Q2"}
STOCK = ((0.0, 100.0), (0.0, 80.0), (-20.0, 0.0))
TOOLS = {1: Tool(2.0, 60.0), 2: Tool(5.0, 80.0), 3: Tool(8.0, 50.0)}
SAFE_START = Rapid(Linear(-50.0), Linear(-50.0), Linear(50.0))
# The transforms each dialect's writer can write. ISO draws G92 or G68, never both (G92
# under a rotation is not defined here); LinuxCNC G52 or G92, never both (they share one
# offset there, a G52 replaces a G92 preset).
FRAMES = {"iso": ("shift", "preset", "rotate"), "linuxcnc": ("shift", "preset"), "sinumerik": ("shift", "rotate", "scale", "mirror"),
          "heidenhain": ("shift", "rotate", "scale", "mirror"), "fagor": ("preset",)}

integers = st.integers


# --------------------------------------------------------------------------- strategies


def _linear(low: int, high: int, factors, in_loop: bool) -> st.SearchStrategy:
    per_pass = st.sampled_from([0.0, 0.0, 10.0, -15.0]) if in_loop else st.just(0.0)
    return st.builds(Linear, integers(low, high).map(float), st.sampled_from(factors), per_pass)


def _moves(in_loop: bool):
    x = _linear(-60, 160, [0.0, 0.0, 1.0, -1.0, 0.5], in_loop)
    y = _linear(-60, 140, [0.0, 0.0, 1.0, -2.0], in_loop)
    z = _linear(-30, 40, [0.0, 0.0, 1.0, -1.0], False)
    return st.builds(Rapid, x, y, z), st.builds(Feed, x, y, z)


half_circles = st.builds(HalfCircle, integers(-15, 15).map(float), integers(-15, 15).map(float), st.booleans()).filter(lambda arc: arc.i or arc.j)


@st.composite
def _drill(draw, in_loop: bool):
    clear = float(draw(integers(5, 50)))
    r = float(draw(integers(-10, int(clear) - 3)))
    xy = _linear(-20, 120, [0.0, 0.0, 1.0, -1.0], in_loop)
    return Drill(draw(xy), draw(xy), clear, r, r - draw(integers(5, 15)))


def _frames(dialect: str, kinds: tuple) -> st.SearchStrategy:
    offsets = integers(-60, 60).map(float)
    made = {"shift": st.builds(Shift, offsets, offsets), "preset": st.builds(Preset, offsets, offsets),
            "rotate": st.sampled_from([0.0, 30.0, 90.0, -45.0, 180.0]).map(Rotate),
            "scale": st.sampled_from([1.0, 0.5, 2.0]).map(lambda factor: Scale(factor, dialect == "heidenhain")),
            "mirror": st.booleans().map(Mirror)}
    return st.one_of(*(made[kind] for kind in kinds))


@st.composite
def cases(draw, dialect: str) -> Case:
    kinds = FRAMES[dialect]
    if dialect == "iso":
        kinds = ("shift", draw(st.sampled_from(["preset", "rotate"])))
    elif dialect == "linuxcnc":
        kinds = (draw(st.sampled_from(kinds)),)
    frames = _frames(dialect, kinds)
    tool_changes = st.sampled_from(sorted(TOOLS)).map(ToolChange)
    rapid, feed = _moves(False)
    rapid_in_loop, feed_in_loop = _moves(True)
    names = iter(range(1, 10))
    plain = [rapid, rapid, rapid, feed, half_circles, frames, tool_changes, _drill(False)]
    loop_body = st.lists(st.one_of(rapid_in_loop, rapid_in_loop, feed_in_loop, half_circles, _drill(True), tool_changes), min_size=1, max_size=3)
    call_body = st.lists(st.one_of(rapid, rapid, feed, half_circles, frames), min_size=1, max_size=3)
    loops = st.builds(Loop, integers(1, 3), loop_body.map(tuple))
    calls = call_body.map(lambda body: Call(f"SUB{next(names)}", tuple(body)))
    steps = draw(st.lists(st.one_of(*plain, loops, calls), min_size=1, max_size=7))
    low = float(draw(integers(-20, 20)))
    offset = tuple(float(draw(integers(-300, 300))) for _ in range(3))
    travel = ((offset[0] + draw(integers(-120, -30)), offset[0] + draw(integers(110, 220))),
              (offset[1] + draw(integers(-120, -30)), offset[1] + draw(integers(90, 200))), (-1e4, 1e4))
    return Case(STOCK, TOOLS, offset, travel, low, low + draw(integers(1, 30)), (SAFE_START, *steps))


# --------------------------------------------------------------------------- writing


class _Text:
    """Lines of the files being written, and the move tags each line carries."""

    def __init__(self, main: str):
        self.files = {main: []}
        self.places: dict[tuple[str, int], set] = {}
        self.file = main

    def line(self, text: str, *tags) -> None:
        lines = self.files[self.file]
        lines.append(text)
        if tags:
            self.places.setdefault((self.file, len(lines)), set()).update(tags)


def _annotations(case: Case, dialect: str, open_: str, close: str) -> list[str]:
    (x_low, x_high), (y_low, y_high), (z_low, z_high) = case.stock
    return [f"{open_}ncverify: stock box X{x_low:g}:{x_high:g} Y{y_low:g}:{y_high:g} Z{z_low:g}:{z_high:g}{close}",
            *(f"{open_}ncverify: tool {number} radius {tool.radius:g} length {tool.length:g}{close}" for number, tool in case.tools.items()),
            f"{open_}ncverify: assume {case.low:g} <= {PARAMETER[dialect]} <= {case.high:g}{close}"]


def project_file(case: Case) -> str:
    """The work offset and the travel, for ``ncverify.toml``."""
    (x_low, x_high), (y_low, y_high), (z_low, z_high) = case.travel
    return (f"[machine]\ntravel = {{ x = [{x_low}, {x_high}], y = [{y_low}, {y_high}], z = [{z_low}, {z_high}] }}\n"
            f"work_offsets = {{ G54 = {list(case.offset)} }}\n")


def _sum(value: Linear, parameter: str, counter: str, number) -> str:
    """``c + f * p + s * k`` as infix text, with the signs written out."""
    text = number(value.constant)
    for factor, name in ((value.factor, parameter), (value.per_pass, counter)):
        if factor:
            text += f" {'-' if factor < 0 else '+'} {number(abs(factor))} * {name}"
    return text


class _Writer:
    """Writes a case's steps in one dialect; each step is tagged with its place in the case."""

    def steps(self, text: _Text, steps: tuple, path: tuple) -> None:
        for index, step in enumerate(steps):
            self.step(text, step, (*path, index))


class _IsoWriter(_Writer):
    """ISO (Mitsubishi E60 / Fanuc macro B), and LinuxCNC with O-words for loops and subprograms."""

    def __init__(self, dialect: str):
        self.dialect, self.loops, self.subprograms = dialect, 0, {}

    @staticmethod
    def number(value: float) -> str:
        return f"{value:.3f}"

    def word(self, value: Linear) -> str:
        if not value.factor and not value.per_pass:
            return self.number(value.constant)
        return f"[{_sum(value, PARAMETER[self.dialect], COUNTER[self.dialect], self.number)}]"

    def write(self, case: Case) -> _Text:
        """Subprograms after the main program in the same file; LinuxCNC's O-word subroutines before it."""
        linuxcnc = self.dialect == "linuxcnc"
        text = _Text("part.ngc" if linuxcnc else "part.nc")
        calls = [(index,) for index, step in enumerate(case.steps) if isinstance(step, Call)]  # calls are drawn at the top level only
        self.subprograms = {tag: 2001 + number for number, tag in enumerate(calls)}
        if not linuxcnc:
            text.line("%")
            text.line("O1000")
        for line in _annotations(case, self.dialect, "(", ")"):
            text.line(line)
        if linuxcnc:
            self.bodies(text, case, "o{} sub", "o{} endsub")
        text.line("G21 G90 G54 G17")
        text.line("T1 M06")
        self.steps(text, case.steps, ())
        text.line("M30")
        if not linuxcnc:
            self.bodies(text, case, "O{}", "M99")
            text.line("%")
        return text

    def bodies(self, text: _Text, case: Case, head: str, tail: str) -> None:
        for tag, number in self.subprograms.items():
            text.line(head.format(number))
            self.steps(text, case.steps[tag[0]].body, tag)
            text.line(tail.format(number))

    def step(self, text: _Text, step, tag: tuple) -> None:
        n = self.number
        if isinstance(step, (Rapid, Feed)):
            code = "G00" if isinstance(step, Rapid) else "G01"
            text.line(f"{code} X{self.word(step.x)} Y{self.word(step.y)} Z{self.word(step.z)}" + ("" if code == "G00" else " F200."), tag)
        elif isinstance(step, HalfCircle):
            text.line(f"G91 G0{2 if step.clockwise else 3} X{n(2 * step.i)} Y{n(2 * step.j)} I{n(step.i)} J{n(step.j)} F200.", tag)
            text.line("G90")
        elif isinstance(step, Drill):
            text.line(f"G00 Z{n(step.clear)}", (*tag, "clear"))
            text.line(f"G98 G81 X{self.word(step.x)} Y{self.word(step.y)} Z{n(step.bottom)} R{n(step.r)} F100.", (*tag, "over"), (*tag, "down"))
            text.line("G80")
        elif isinstance(step, Loop):
            self.loops += 1
            counter = COUNTER[self.dialect]
            linuxcnc = self.dialect == "linuxcnc"
            text.line(f"{counter} = 0")
            text.line(f"o{100 + self.loops} while [{counter} LT {step.count}]" if linuxcnc else f"WHILE [{counter} LT {step.count}] DO1")
            self.steps(text, step.body, tag)
            text.line(f"{counter} = [{counter} + 1]")
            text.line(f"o{100 + self.loops} endwhile" if linuxcnc else "END1")
        elif isinstance(step, Call):
            number = self.subprograms[tag]
            text.line(f"o{number} call" if self.dialect == "linuxcnc" else f"M98 P{number}")
        elif isinstance(step, ToolChange):
            text.line(f"T{step.number} M06")
        elif isinstance(step, Shift):
            text.line(f"G52 X{n(step.x)} Y{n(step.y)}")
        elif isinstance(step, Preset):
            text.line(f"G92 X{n(step.x)} Y{n(step.y)}")
        elif isinstance(step, Rotate):
            text.line(f"G68 X0. Y0. R{n(step.degrees)}" if step.degrees else "G69")
        else:
            raise TypeError(step)


class _SinumerikWriter(_Writer):
    def __init__(self):
        self.frame = {"shift": (0.0, 0.0), "mirror": False, "degrees": 0.0, "factor": 1.0}

    @staticmethod
    def word(value: Linear) -> str:
        if not value.factor and not value.per_pass:
            return f"{value.constant:g}"
        return f"({_sum(value, 'R1', 'R2', lambda number: f'{number:g}')})"

    def write(self, case: Case) -> _Text:
        text = _Text("part.mpf")
        for line in _annotations(case, "sinumerik", "; ", ""):
            text.line(line)
        text.line("G17 G90 G54 G71")
        text.line("T1 D1 M6")
        self.steps(text, case.steps, ())
        text.line("M30")
        return text

    def step(self, text: _Text, step, tag: tuple) -> None:
        w = self.word
        if isinstance(step, (Rapid, Feed)):
            code = "G0" if isinstance(step, Rapid) else "G1"
            text.line(f"{code} X={w(step.x)} Y={w(step.y)} Z={w(step.z)}" + ("" if code == "G0" else " F200"), tag)
        elif isinstance(step, HalfCircle):
            text.line(f"G{2 if step.clockwise else 3} X=IC({2 * step.i:g}) Y=IC({2 * step.j:g}) I={step.i:g} J={step.j:g} F200", tag)
        elif isinstance(step, Drill):
            text.line(f"G0 Z{step.clear:g}", (*tag, "clear"))
            text.line(f"G0 X={w(step.x)} Y={w(step.y)}", (*tag, "over"))
            text.line(f"CYCLE81({step.clear:g}, {step.r - 2:g}, 2, {step.bottom:g})", (*tag, "down"))
        elif isinstance(step, Loop):
            text.line(f"FOR R2 = 0 TO {step.count - 1}")
            self.steps(text, step.body, tag)
            text.line("ENDFOR")
        elif isinstance(step, Call):
            caller = text.file
            text.line(step.name)
            text.file = f"{step.name}.SPF"
            text.files[text.file] = []
            self.steps(text, step.body, tag)
            text.line("M17")
            text.file = caller
        elif isinstance(step, ToolChange):
            text.line(f"T{step.number} D1 M6")
        else:
            self.frame_step(text, step)

    def frame_step(self, text: _Text, step) -> None:
        """The whole programmable frame, written again: TRANS replaces it, the A- forms append."""
        frame = self.frame
        if isinstance(step, Shift):
            frame["shift"] = (step.x, step.y)
        elif isinstance(step, Rotate):
            frame["degrees"] = step.degrees
        elif isinstance(step, Scale):
            frame["factor"] = step.factor
        elif isinstance(step, Mirror):
            frame["mirror"] = step.on
        else:
            raise TypeError(step)
        text.line(f"TRANS X={frame['shift'][0]:g} Y={frame['shift'][1]:g}")
        if frame["mirror"]:
            text.line("AMIRROR X0")
        if frame["degrees"]:
            text.line(f"AROT RPL={frame['degrees']:g}")
        if frame["factor"] != 1.0:
            text.line(f"ASCALE X={frame['factor']:g} Y={frame['factor']:g}")


class _KlartextWriter(_Writer):
    def __init__(self):
        self.labels = 0
        self.subprograms = []

    @staticmethod
    def set_q(text: _Text, values) -> None:
        for number, value in zip((10, 11, 12), values):
            text.line(f"Q{number} = {_sum(value, 'Q1', 'Q2', lambda n: f'{n:g}')}")

    def write(self, case: Case) -> _Text:
        text = _Text("part.h")
        text.line("BEGIN PGM ORACLE MM")
        for line in _annotations(case, "heidenhain", "; ", ""):
            text.line(line)
        text.line("TOOL CALL 1 Z S3000")
        self.steps(text, case.steps, ())
        text.line("M30")
        for label, path, body in self.subprograms:
            text.line(f"LBL {label}")
            self.steps(text, body, path)
            text.line("LBL 0")
        text.line("END PGM ORACLE MM")
        lines = text.files["part.h"]
        number = 0
        for index, line in enumerate(lines):
            if not line.startswith("    "):  # a continuation line of a cycle definition has no block number
                lines[index] = f"{number} {line}"
                number += 1
        return text

    def step(self, text: _Text, step, tag: tuple) -> None:
        if isinstance(step, (Rapid, Feed)):
            self.set_q(text, (step.x, step.y, step.z))
            text.line("L X+Q10 Y+Q11 Z+Q12 R0 " + ("FMAX" if isinstance(step, Rapid) else "F200"), tag)
        elif isinstance(step, HalfCircle):
            text.line(f"CC IX{step.i:+g} IY{step.j:+g}")
            text.line(f"C IX{2 * step.i:+g} IY{2 * step.j:+g} DR{'-' if step.clockwise else '+'} F200", tag)
        elif isinstance(step, Drill):
            surface = step.r - 2
            text.line(f"L Z{step.clear:+g} R0 FMAX", (*tag, "clear"))
            text.line("CYCL DEF 200 DRILLING ~")
            for q, value, what in ((200, 2, "SET-UP CLEARANCE"), (201, step.bottom - surface, "DEPTH"), (206, 150, "FEED RATE FOR PLNGNG"),
                                   (202, surface - step.bottom, "PLUNGING DEPTH"), (210, 0, "DWELL TIME AT TOP"), (203, surface, "SURFACE COORDINATE"),
                                   (204, step.clear - surface, "2ND SET-UP CLEARANCE")):
                text.line(f"    Q{q}={value:+g} ;{what}" + ("" if q == 204 else " ~"))
            self.set_q(text, (step.x, step.y, Linear(0.0)))
            text.line("L X+Q10 Y+Q11 R0 FMAX M99", (*tag, "over"), (*tag, "down"))
        elif isinstance(step, Loop):
            self.labels += 1
            label = 10 + self.labels
            text.line("Q2 = 0")
            text.line(f"LBL {label}")
            self.steps(text, step.body, tag)
            text.line("Q2 = Q2 + 1")
            if step.count > 1:
                text.line(f"CALL LBL {label} REP {step.count - 1}")
        elif isinstance(step, Call):
            label = len(self.subprograms) + 1
            self.subprograms.append((label, tag, step.body))
            text.line(f"CALL LBL {label}")
        elif isinstance(step, ToolChange):
            text.line(f"TOOL CALL {step.number} Z S3000")
        elif isinstance(step, Shift):
            text.line("CYCL DEF 7.0 DATUM SHIFT")
            text.line(f"CYCL DEF 7.1 X{step.x:+g}")
            text.line(f"CYCL DEF 7.2 Y{step.y:+g}")
        elif isinstance(step, Rotate):
            text.line("CYCL DEF 10.0 ROTATION")
            text.line(f"CYCL DEF 10.1 ROT{step.degrees:+g}")
        elif isinstance(step, Scale):
            text.line("CYCL DEF 11.0 SCALING")
            text.line(f"CYCL DEF 11.1 SCL{step.factor:g}")
        elif isinstance(step, Mirror):
            text.line("CYCL DEF 8.0 MIRROR IMAGE")
            text.line("CYCL DEF 8.1 X" if step.on else "CYCL DEF 8.1")
        else:
            raise TypeError(step)


class _FagorWriter(_Writer):
    def __init__(self):
        self.subprograms = []

    @staticmethod
    def set_p(text: _Text, values) -> None:
        for number, value in zip((10, 11, 12), values):
            text.line(f"P{number} = {_sum(value, 'P1', 'P2', lambda n: f'{n:g}')}")

    def write(self, case: Case) -> _Text:
        text = _Text("part.pim")
        for line in _annotations(case, "fagor", "; ", ""):
            text.line(line)
        text.line("G17 G90 G54")
        text.line("T1 D1 M6")
        self.steps(text, case.steps, ())
        text.line("M30")
        for name, path, body in self.subprograms:
            text.line(f"%L {name}")
            self.steps(text, body, path)
            text.line("#RET")
        return text

    def step(self, text: _Text, step, tag: tuple) -> None:
        if isinstance(step, (Rapid, Feed)):
            self.set_p(text, (step.x, step.y, step.z))
            text.line("G0 X P10 Y P11 Z P12" if isinstance(step, Rapid) else "G1 X P10 Y P11 Z P12 F200", tag)
        elif isinstance(step, HalfCircle):
            text.line(f"G91 G{2 if step.clockwise else 3} X{2 * step.i:g} Y{2 * step.j:g} I{step.i:g} J{step.j:g} F200", tag)
            text.line("G90")
        elif isinstance(step, Drill):
            text.line(f"G0 Z{step.clear:g}", (*tag, "clear"))
            self.set_p(text, (step.x, step.y, Linear(0.0)))
            text.line(f"G0 G98 G81 X P10 Y P11 Z{step.r:g} I{step.bottom:g} F100", (*tag, "over"), (*tag, "down"))
            text.line("G80")
        elif isinstance(step, Loop):
            text.line(f"$FOR P2 = 0, {step.count - 1}, 1")
            self.steps(text, step.body, tag)
            text.line("$ENDFOR")
        elif isinstance(step, Call):
            self.subprograms.append((step.name, tag, step.body))
            text.line(f"#CALL {step.name}")
        elif isinstance(step, ToolChange):
            text.line(f"T{step.number} D{step.number} M6")
        elif isinstance(step, Preset):
            text.line(f"G92 X{step.x:g} Y{step.y:g}")
        else:
            raise TypeError(step)


def write(dialect: str, case: Case) -> _Text:
    """The program of ``case`` in ``dialect``: its files (the main one first) and the tags per line."""
    if dialect in ("iso", "linuxcnc"):
        return _IsoWriter(dialect).write(case)
    return {"sinumerik": _SinumerikWriter, "heidenhain": _KlartextWriter, "fagor": _FagorWriter}[dialect]().write(case)


DIALECTS = ("fagor", "heidenhain", "iso", "linuxcnc", "sinumerik")
