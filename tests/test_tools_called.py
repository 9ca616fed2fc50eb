"""The tools a program's text can load, which set the cut stock's cells (a quarter of the
smallest radius among them): what the scan of the text says against what the interpreter
puts in the spindle, and what it changes for the stock model."""
from __future__ import annotations

import pytest
from hypothesis import given, settings, strategies as st

from ncverify import Settings, check_text
from ncverify.api import check_source
from ncverify.check import Checker
from ncverify.source import ProgramSource

_TABLE = "".join(f"(ncverify: tool {number} radius {radius} type endmill)\n" for number, radius in ((1, 4), (2, 0.5), (3, 2), (4, 1), (5, 3)))


def _called_and_loaded(program: str, path: str):
    """(what the scan said, the tools that were in the spindle at any move) of a check."""
    seen: dict = {"loaded": set()}

    class Watching(Checker):
        def __init__(self, *arguments, **keywords):
            super().__init__(*arguments, **keywords)
            seen["called"] = self.context.tools_called

        def segment(self, segment, state):
            seen["loaded"].add(state.tool_in_spindle)
            super().segment(segment, state)

        def motion_run(self, run, state):
            seen["loaded"].add(state.tool_in_spindle)
            super().motion_run(run, state)

    check_source(ProgramSource.from_text(program, path), Settings(), None, checker_class=Watching)
    return seen["called"], {tool for tool in seen["loaded"] if tool is not None}


_NUMBER = st.integers(1, 5)
_LINE = st.one_of(
    _NUMBER.map(lambda n: f"T{n} M06"), _NUMBER.map(lambda n: f"T0{n} M6"), _NUMBER.map(lambda n: f"M6 T {n}"),
    _NUMBER.map(lambda n: f"G0 X1. Y2. T{n}"), _NUMBER.map(lambda n: f"(T{n} DRILL)"), _NUMBER.map(lambda n: f"#1 = {n}"),
    st.sampled_from(["T#1 M6", "T[#1 + 1] M6", "M6", "G10 L1 P2 R0.1", "G0 X5. Y5. Z5.", "G1 X10. F100.", "G0Z50.", "(SETUP NOTE)"]),
)


@settings(max_examples=150, deadline=None)
@given(st.lists(_LINE, min_size=1, max_size=12), st.sampled_from(["t.nc", "t.ngc"]))
def test_every_tool_the_interpreter_loads_is_one_the_scan_names(lines, path):
    """Tool words of every form, computed numbers, tool table writes, comments: the scan
    names every tool that reaches the spindle, or says it cannot tell (None)."""
    body = "\n".join(line for line in lines for line in (line, "G0 X1. Y1. Z5."))
    called, loaded = _called_and_loaded(f"{_TABLE}G21 G90 G17 G54\n{body}\nM30\n", path)
    assert called is None or {int(tool) for tool in loaded if type(tool) is float} <= called


@pytest.mark.parametrize(("text", "called"), [
    ("T1 M6\nG0 X0\nT03 M06\n(T5 IS THE DRILL)\nM30\n", {1, 3, 5}),
    ("G0 X0\nM30\n", None),  # no tool called: the one in the spindle cuts
    ("#1 = 2\nT#1 M6\nM30\n", None),
    ("T1 M6\nM98 P2000\nM30\n", None),  # the subprogram may be a file of its own
    ("T1 M6\nG65 P9010 A1.\nM30\n", None),
    ("T1 M6\nG10 L12 P1 R0.2\nM30\n", None),  # tool offsets written by the program
    ("G0M98P100\nT1M6\nM30\n", None),
    ("T1 M6\n(T" + "9" * 5000 + ")\nM30\n", None),  # a number no table holds, past what int() reads from text
])
def test_the_iso_scan_names_the_t_words_or_says_it_cannot_tell(text, called):
    assert _called_and_loaded(_TABLE + text, "t.nc")[0] == (None if called is None else frozenset(called))


def test_a_lathe_s_tool_words_are_not_read_as_tool_numbers():
    """``T0101`` on a lathe is tool 1 with offset 1, not tool 101 (found on the Haas lathe
    programs of the third-party corpus): a lathe's text is not scanned (its bar keeps no
    cells to choose)."""
    program = "(ncverify: machine lathe)\n" + _TABLE + "G18 G21 G40 G99\nT0101\nG97 S1000 M03\nG00 X20. Z2.\nM30\n"
    called, loaded = _called_and_loaded(program, "t.nc")
    assert called is None and 1.0 in loaded


@pytest.mark.parametrize(("text", "called"), [
    ("T1 M6\no100 sub\nT2 M6\no100 endsub\no100 call\nM2\n", {1, 2}),
    ("T1 M6\no<pocket> sub\nT4 M6\no<pocket> endsub\no<pocket> call\nM2\n", {1, 4}),
    ("T1 M6\no<elsewhere> call\nM2\n", None),  # a file of its own
    ("T1 M6\n(o<elsewhere> sub is in its own file)\no<elsewhere> call\nM2\n", None),  # a comment defines no subroutine
    ("T1 M6\nM61 Q2\nM2\n", None),  # sets the tool number without a T word
])
def test_the_linuxcnc_scan_looks_into_the_file_s_own_subroutines_only(text, called):
    assert _called_and_loaded(_TABLE + text, "t.ngc")[0] == (None if called is None else frozenset(called))


@pytest.mark.parametrize(("text", "called"), [
    ("TOOL CALL 1 Z S3000\nL X+0 Y+0 R0 FMAX\nTOOL CALL 4 Z S2000\nTOOL CALL Z S1000\n", {1, 4}),
    ('TOOL CALL "MILL_D8" Z S3000\n', None),
    ("TOOL CALL Q5 Z S3000\n", None),
    ("TOOL CALL 1 Z S3000\nCALL PGM TNC:\\PARTS\\FINISH.H\n", None),
    ("TOOL CALL 1 Z S3000\nFN 17: SYSWRITE ID 50 NR 1 IDX1 = 0.2\n", None),
])
def test_the_klartext_scan_names_the_numbered_tool_calls_or_says_it_cannot_tell(text, called):
    table = "".join(f"; {line[1:-1]}\n" for line in _TABLE.splitlines())  # a Klartext comment
    program = f"0 BEGIN PGM T MM\n{table}{text}99 END PGM T MM\n"
    assert _called_and_loaded(program, "t.h")[0] == (None if called is None else frozenset(called))


def _stock_note(program: str, **options):
    return [d.status.value for d in check_text(program, "t.nc", Settings(**options)).diagnostics if d.rule == "core.stock-model-too-large"]


def test_a_fine_tool_the_program_never_loads_does_not_make_its_cells_fine():
    """A magazine's engraver (0.05 mm) in the table and a 4 mm end mill in the program: the
    cells come from the end mill, so a blank that fits at its cells is modelled. Once the
    program loads the engraver too, the cells it needs do not fit, and the finding says so."""
    table = "(ncverify: stock box X0:200 Y0:200 Z-20:0)\n(ncverify: tool 1 radius 4 type endmill)\n(ncverify: tool 9 radius 0.05 type endmill)\n"
    cutting = "G21 G90 G17 G54\nT1 M06\nG43 H01 Z50.\nS6000 M03\nG00 X50. Y30.\nZ2.\nG01 Z-5. F200.\nX80.\nG00 Z50.\n"
    cap = 1 << 20  # 1 MiB: 1 mm cells of this blank fit, 0.05 mm cells do not
    assert _stock_note(table + cutting + "M30\n", stock_memory=cap) == []
    assert _stock_note(table + cutting + "T9 M06\nM30\n", stock_memory=cap) == ["unknown"]
