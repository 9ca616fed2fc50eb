"""The LinuxCNC dialect on its own: detection, expressions, O-word control flow, tool table."""
from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st

from ncverify import Settings, check_file, check_text
from ncverify.detect import detect
from ncverify.lower.linuxcnc import read_tool_table
from rs274 import run_ncverify
from test_read_iso import plain_blocks

CORPUS = Path(__file__).resolve().parent.parent.parent / "shared" / "corpus-realworld" / "linuxcnc"


def _ends(program: str) -> list[tuple]:
    ours, _trace = run_ncverify(program)
    return [point[:3] for line in sorted(ours.moves) for point in ours.moves[line]]


def test_detected_from_o_words_named_parameters_and_active_comments():
    assert detect("o100 sub\nG1 X#1\no100 endsub\nM2\n").dialect == "linuxcnc"
    assert detect("#<depth> = 2\nG1 Z-#<depth> F100 ; cut\nM2\n").dialect == "linuxcnc"
    assert detect("G0 X1\n(print, hello)\n(debug, #1)\nM30\n").dialect == "linuxcnc"
    assert detect("O1000\nG0 X1.\n#1=2\nM30\n").dialect == "iso"


def test_every_corpus_program_is_checked_as_linuxcnc():
    """O-words, named parameters and active comments tell most; plain G-code by its .ngc name."""
    if not CORPUS.is_dir():
        pytest.skip("the real-world LinuxCNC corpus is not here")
    wrong = [path.name for path in sorted(CORPUS.glob("*.ngc")) if check_file(path).dialect != "linuxcnc"]
    assert wrong == []


def test_expression_precedence_power_before_product_and_logical_operators():
    ends = _ends("G0 X[2 + 3 * 2 ** 2] Y[1 AND 2] Z[0 OR 0]\nM2\n")
    assert ends == [(14.0, 1.0, 0.0)]


def test_if_elseif_else_takes_one_branch():
    program = "#<a> = 2\no1 if [#<a> EQ 1]\nG0 X1\no1 elseif [#<a> EQ 2]\nG0 X2\no1 else\nG0 X3\no1 endif\nM2\n"
    assert [point[0] for point in _ends(program)] == [2.0]


def test_do_while_runs_its_body_before_testing_and_break_leaves_a_loop():
    program = ("#1 = 0\no2 do\n#1 = [#1 + 1]\nG0 X#1\no2 while [#1 LT 3]\n"
               "o3 while [1]\nG0 Y5\no3 break\no3 endwhile\nM2\n")
    assert _ends(program) == [(1.0, None, None), (2.0, None, None), (3.0, None, None), (3.0, 5.0, None)]


def test_subroutine_arguments_are_local_and_return_a_value():
    program = ("o<twice> sub\n#<local> = [#1 * 2]\no<twice> endsub [#<local>]\n"
               "o<twice> call [4]\nG0 X#<_value>\nG0 Y[EXISTS[#<local>]]\nM2\n")
    assert _ends(program) == [(8.0, None, None), (8.0, 0.0, None)]


def test_reading_a_named_parameter_never_set_is_a_finding():
    result = check_text("G21\nG0 X[#<nowhere> + 1]\nM2\n", "t.ngc", Settings(dialect="linuxcnc"))
    assert any(finding.rule == "core.undefined-variable" and finding.span.line == 2 for finding in result.diagnostics)


def test_an_endless_while_loop_hits_the_loop_bound():
    result = check_text("o1 while [1]\nG91 G0 X1\no1 endwhile\nM2\n", "t.ngc", Settings(dialect="linuxcnc", loop_bound=50))
    assert any(finding.rule == "core.loop-bound" for finding in result.diagnostics)


def test_tool_table_lines_give_number_radius_and_length():
    tools = read_tool_table("T1 P1 D6.0 Z-12.5 ;end mill\n;comment\nT7 P3 Z0.5 D0.25\n")
    assert (tools[1].radius, tools[1].length) == (3.0, -12.5)
    assert (tools[7].radius, tools[7].length) == (0.125, 0.5)


def test_a_tool_table_line_with_a_number_too_large_for_a_float_is_left_out():
    tools = read_tool_table(f"T1 P1 D{'9' * 400} Z-12.5\nT{'9' * 400} P2 D6\nT2 P2 D6 Z1\n")
    assert set(tools) == {2}


_LINE_PIECES = st.sampled_from(["G1", "X", "#<a>", "#1", "=", "[", "]", "1.5", "-", "**", "AND", "o100", "o<s>", "sub", "if",
                                "endif", "call", "while", "do", "(c)", "(abort,x)", ";x", "@", "^", "EXISTS", "ATAN", "/", "M98",
                                "O1", "N10", " ", "SIN"])


@settings(max_examples=300, deadline=None)
@given(st.lists(st.lists(_LINE_PIECES, max_size=8).map("".join), min_size=1, max_size=6))
def test_any_text_is_read_and_run_without_a_crash(lines):
    """Whatever the lines hold, the reader, the lowering and the interpreter answer with
    findings, never an exception."""
    result = check_text("\n".join(lines) + "\nM2\n", "t.ngc", Settings(dialect="linuxcnc", loop_bound=20))
    assert result.dialect == "linuxcnc"


def test_tool_table_beside_the_program_is_its_context(tmp_path):
    (tmp_path / "tool.tbl").write_text("T1 P1 D6.0 Z0 ;end mill\n", encoding="ascii")
    program = tmp_path / "part.ngc"
    program.write_text("G21 G90\nT5 M6\nG43 H5\nM2\n", encoding="ascii")
    assert any(finding.rule == "core.tool-not-in-table" for finding in check_file(program).diagnostics)
    program.write_text("G21 G90\nT1 M6\nG43 H1\nM2\n", encoding="ascii")
    assert not any(finding.rule == "core.tool-not-in-table" for finding in check_file(program).diagnostics)


def test_a_subroutine_file_is_found_by_its_name(tmp_path):
    (tmp_path / "corner.ngc").write_text("o<corner> sub\nG1 X#1 Y#2 F100\no<corner> endsub\nM2\n", encoding="ascii")
    program = "G21 G90 G0 X0 Y0 Z5\no<corner> call [3] [4]\nG0 X[#5420 + 1]\nM2\n"
    ours, trace = run_ncverify(program, tmp_path, "main.ngc")
    assert [point[:3] for point in ours.moves[3]] == [(4.0, 4.0, 5.0)]
    assert "core.program-not-found" not in {rule for rule, _line, _status in trace.findings}


def test_the_words_of_an_m_code_are_not_a_hole_of_a_modal_cycle():
    program = "G21 G90 G0 X0 Y0 Z5\nG99 G81 X1 Y1 Z-2 R1 F100\nM66 P0 L3 Q2\nM19 R90 Q2\nX2\nG80\nM2\n"
    ours, _trace = run_ncverify(program)
    assert 3 not in ours.moves and 4 not in ours.moves
    assert ours.moves[5][-1][:3] == (2.0, 1.0, 1.0)


@settings(max_examples=300, deadline=None)
@given(block=plain_blocks(), line=st.integers(min_value=1, max_value=10**6))
def test_plain_motion_and_arc_lines_lower_fast_like_the_linuxcnc_lowering(block, line):
    """LinuxCNC shares ISO's fast lowering of plain motion and arc lines; the IR must be
    the one its own reader and lowering make."""
    from ncverify.lower.linuxcnc import LinuxcncFrontend, LinuxcncLowering, linuxcnc_table

    text, _ = block
    frontend = LinuxcncFrontend(LinuxcncLowering(linuxcnc_table()))
    assert frontend.blocks(text.encode("ascii"), line, None) == frontend._lower_text(text, line, None)
