"""Bad input ends in bounded time with a clear message and no traceback: binary junk,
broken comments, files over the size limit, endless loops and recursion, unknown codes,
arithmetic on vacant variables, and a long file of nothing but syntax errors."""
from __future__ import annotations

import json
import random
import time

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ncverify import InputError, Settings, check_file, check_text
from ncverify.api import check_source
from ncverify.cli import main
from ncverify.diagnostics import Status
from ncverify.source import ProgramSource


def cli(capsys, *arguments) -> tuple[int, str, str]:
    try:
        code = main([str(argument) for argument in arguments])
    except SystemExit as exit_:
        code = exit_.code
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return code, out, err


def junk(size: int, seed: int = 7) -> bytes:
    generator = random.Random(seed)
    data = bytearray(generator.getrandbits(8) for _ in range(size))
    data[::97] = bytes(len(data[::97]))  # NULs sprinkled through it
    return bytes(data)


from conftest import findings


# --------------------------------------------------------------------------- binary junk


def test_binary_junk_named_on_the_command_line_exits_2_saying_it_is_binary(tmp_path, capsys):
    path = tmp_path / "dump.nc"
    path.write_bytes(junk(20_000))
    started = time.perf_counter()
    code, out, err = cli(capsys, "check", path)
    assert time.perf_counter() - started < 10
    assert code == 2
    assert "binary data, not a CNC program" in out + err


def test_binary_junk_in_a_folder_is_skipped_and_does_not_fail_the_run(tmp_path, capsys):
    (tmp_path / "dump.nc").write_bytes(junk(5_000))
    (tmp_path / "part.nc").write_text("G21 G90\nG0 X0. Y0.\nM30\n", encoding="utf-8")
    code, out, _ = cli(capsys, "check", tmp_path)
    assert code == 0
    assert "dump.nc: note: skipped: binary data" in out


def test_binary_junk_through_the_api_is_skipped_not_checked(tmp_path):
    path = tmp_path / "dump.nc"
    path.write_bytes(junk(3_000))
    result = check_file(path)
    assert result.dialect is None and "binary" in result.skipped
    assert result.diagnostics == []


def test_binary_junk_is_skipped_even_when_the_dialect_is_forced(tmp_path):
    path = tmp_path / "dump.nc"
    path.write_bytes(junk(3_000))
    result = check_file(path, Settings(dialect="iso"))
    assert result.skipped and "binary" in result.skipped


def test_binary_junk_after_a_valid_head_gives_syntax_findings_at_the_bad_characters():
    data = b"O1000\nG21 G90\n" + b"G0 X1.\n" * 2000 + b"G0 X\x002.\n" + junk(2_000) + b"\nM30\n"
    result = check_source(ProgramSource.from_bytes(data, "late-junk.nc"), Settings(loop_bound=50))
    assert result.skipped is None
    first = min(findings(result, "core.syntax"), key=lambda d: d.span.line)
    assert (first.span.line, first.span.column) == (2003, 5)
    assert "U+0000" in first.message


@settings(max_examples=60, deadline=None)
@given(data=st.binary(max_size=600))
def test_any_bytes_are_either_skipped_or_checked_without_raising(data):
    result = check_source(ProgramSource.from_bytes(data, "fuzz.nc"), Settings(loop_bound=50, dialect="iso"))
    assert result.skipped is not None or result.dialect == "iso"


# --------------------------------------------------------------------------- broken text


def test_an_unterminated_comment_is_a_syntax_error_at_the_parenthesis(tmp_path, capsys):
    path = tmp_path / "comment.nc"
    path.write_text("G21 G90\nG0 X1. (ROUGHING\nG0 X2.\nM30\n", encoding="utf-8")
    code, out, _ = cli(capsys, "check", "--format", "json", path)
    [syntax] = [d for d in json.loads(out)["files"][0]["diagnostics"] if d["rule"] == "core.syntax"]
    assert (syntax["line"], syntax["column"], syntax["end_column"]) == (2, 8, 17)
    assert "not closed" in syntax["message"]
    assert code == 1


def test_an_unterminated_comment_does_not_swallow_the_next_line():
    result = check_text("G21 G90\nG0 X1. (ROUGHING\nG1 X2.\nM30\n", "t.nc")
    assert [d.span.line for d in findings(result, "core.feed-missing")] == [3]


def test_an_unknown_g_code_is_reported_at_its_word():
    result = check_text("G21 G90\nG123 X1.\nM30\n", "t.nc")
    [unknown] = findings(result, "core.unknown-code")
    assert (unknown.span.line, unknown.span.column, unknown.span.end_column) == (2, 1, 5)
    assert "G123" in unknown.message


def test_an_unknown_g_code_makes_the_position_unknown_not_wrong():
    result = check_text("G21 G91 G0 X5.\nG123 X1.\n#3000=#5001\nM30\n", "t.nc")
    [alarm] = findings(result, "core.macro-alarm")
    assert "#3000=?" in alarm.message  # not 6: G123 may have moved X anywhere


# --------------------------------------------------------------------------- size limit


def test_a_file_over_the_size_limit_exits_2_without_being_read(tmp_path, capsys):
    path = tmp_path / "big.nc"
    path.write_text("G0 X1. Y1.\n" * 200, encoding="utf-8")  # 2,200 bytes
    code, out, err = cli(capsys, "check", "--max-file-size", "1000", path)
    assert code == 2
    assert "larger than the limit" in out + err and "--max-file-size" in out + err


def test_a_file_at_the_size_limit_is_checked(tmp_path, capsys):
    path = tmp_path / "small.nc"
    path.write_bytes(b"G21 G90\nG0 X1.\nM30\n")
    code, _, _ = cli(capsys, "check", "--max-file-size", str(path.stat().st_size), path)
    assert code == 0


def test_the_api_raises_input_error_for_a_file_over_the_limit(tmp_path):
    path = tmp_path / "big.nc"
    path.write_bytes(b"G0 X1.\n" * 300)
    with pytest.raises(InputError, match="larger than the limit"):
        check_file(path, Settings(max_file_bytes=1000))


def test_the_api_raises_input_error_for_a_missing_file(tmp_path):
    with pytest.raises(InputError, match="cannot read"):
        check_file(tmp_path / "gone.nc")


def test_the_api_raises_input_error_for_a_folder(tmp_path):
    with pytest.raises(InputError, match="folder"):
        check_file(tmp_path)


# --------------------------------------------------------------------------- endless programs


def test_an_endless_while_loop_ends_with_loop_bound_unknown_at_the_default_bound(tmp_path, capsys):
    path = tmp_path / "loop.nc"
    path.write_text("G21 G90\nWHILE [1 EQ 1] DO1\nG0 X1.\nEND1\nM30\n", encoding="utf-8")
    started = time.perf_counter()
    code, out, _ = cli(capsys, "check", "--format", "json", path)
    assert time.perf_counter() - started < 20
    [bound] = [d for d in json.loads(out)["files"][0]["diagnostics"] if d["rule"] == "core.loop-bound"]
    assert bound["status"] == "unknown" and bound["line"] == 4
    assert code == 0  # an unknown verdict fails the run only with --fail-on-unknown


def test_an_endless_goto_loop_ends_with_loop_bound_unknown():
    started = time.perf_counter()
    result = check_text("N1 G0 X1.\nG0 X2.\nGOTO 1\nM30\n", "t.nc", Settings(loop_bound=500))
    assert time.perf_counter() - started < 10
    [bound] = findings(result, "core.loop-bound")
    assert bound.status is Status.UNKNOWN


def test_an_endless_m99_in_the_main_program_is_reported_not_followed():
    started = time.perf_counter()
    result = check_text("G21 G90\nG0 X1.\nM99\n", "t.nc")
    assert time.perf_counter() - started < 10
    assert findings(result, "core.m99-in-main")


def test_recursion_through_m98_stops_at_the_call_depth(tmp_path, capsys):
    path = tmp_path / "recursion.nc"
    path.write_text("O1\nM98 P2\nM30\nO2\nG91 G0 X1.\nM98 P2\nM99\n", encoding="utf-8")
    started = time.perf_counter()
    code, out, _ = cli(capsys, "check", path)
    assert time.perf_counter() - started < 10
    assert "core.call-depth" in out
    assert code == 1


def test_mutual_recursion_through_g65_stops_at_the_call_depth():
    result = check_text("O1\nG65 P2\nM30\nO2\nG65 P3\nM99\nO3\nG65 P2\nM99\n", "t.nc")
    assert findings(result, "core.call-depth")


def test_a_subprogram_repeated_a_million_times_is_bounded():
    started = time.perf_counter()
    result = check_text("O1\nM98 P2 L9999\nM98 P2 L9999\nM30\nO2\nG91 G0 X1.\nM99\n", "t.nc", Settings(loop_bound=200))
    assert time.perf_counter() - started < 10
    assert findings(result, "core.loop-bound")


# --------------------------------------------------------------------------- vacant variables


def test_arithmetic_on_the_vacant_variable_is_reported_at_the_variable():
    result = check_text("#100 = #0 + 1\nM30\n", "t.nc")
    [vacant] = findings(result, "core.undefined-variable")
    assert (vacant.span.line, vacant.span.column, vacant.span.end_column) == (1, 8, 10)


def test_dividing_by_a_vacant_macro_variable_is_reported_twice_over():
    result = check_text("O1\nG65 P2\nM30\nO2\n#100 = 1 / #5\nM99\n", "t.nc")
    assert [d.span.column for d in findings(result, "core.undefined-variable")] == [12]
    assert findings(result, "core.arithmetic-domain")


def test_arithmetic_on_a_global_nobody_set_treats_it_as_a_free_parameter():
    result = check_text("#100 = #101 * 2 + 1\nG0 X#100\nM30\n", "t.nc")
    assert "#101" in result.free_parameters
    assert not findings(result, "core.undefined-variable")


def test_a_square_root_of_a_negative_number_is_a_domain_error():
    result = check_text("#100 = SQRT[-4]\nM30\n", "t.nc")
    [domain] = findings(result, "core.arithmetic-domain")
    assert domain.span.line == 1


# --------------------------------------------------------------------------- generated macro programs

_ATOMS = st.sampled_from(["1", "0", "2.5", "-3", "#1", "#2", "#3", "#100", "#0", "#5001", "#4120", "[#1+1]", "#[#1]"])
_FUNCTIONS = st.sampled_from(["SIN", "COS", "TAN", "SQRT", "ABS", "FIX", "FUP", "ROUND", "LN", "EXP", "ASIN", "ACOS", "ATAN", "BIN", "BCD"])
_OPERATORS = st.sampled_from(["+", "-", "*", "/", "MOD", "AND", "OR", "XOR"])
_RELATIONS = st.sampled_from(["EQ", "NE", "LT", "LE", "GT", "GE"])
_EXPRESSIONS = st.recursive(_ATOMS, lambda inner: st.one_of(
    st.tuples(inner, _OPERATORS, inner).map(lambda t: f"[{t[0]} {t[1]} {t[2]}]"),
    st.tuples(_FUNCTIONS, inner).map(lambda t: f"{t[0]}[{t[1]}]"),
    inner.map(lambda e: f"-{e}"),
), max_leaves=8)
_MACRO_LINES = st.one_of(
    st.tuples(st.sampled_from(["#1", "#2", "#3", "#100", "#101"]), _EXPRESSIONS).map(lambda t: f"{t[0]}={t[1]}"),
    st.tuples(_EXPRESSIONS, _RELATIONS, _EXPRESSIONS).map(lambda t: f"IF [{t[0]} {t[1]} {t[2]}] GOTO 10"),
    st.tuples(_EXPRESSIONS, _RELATIONS, _EXPRESSIONS).map(lambda t: f"IF [{t[0]} {t[1]} {t[2]}] THEN #101={t[0]}"),
    st.tuples(st.sampled_from(["G0", "G1", "G91 G1", "G90 G2", "G3"]), _EXPRESSIONS, _EXPRESSIONS).map(lambda t: f"{t[0]} X{t[1]} Y{t[2]} R5. F100."),
    st.tuples(_EXPRESSIONS, _EXPRESSIONS).map(lambda t: f"G99 G81 X{t[0]} Z{t[1]} R2. F100."),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(_MACRO_LINES, min_size=1, max_size=8), machine=st.sampled_from(["mill", "lathe"]))
def test_generated_macro_programs_are_checked_without_raising(body, machine):
    result = check_text("\n".join(body) + "\nN10 M30\n", "macro.nc", Settings(loop_bound=50, machine=machine, max_paths=8))
    assert result.dialect == "iso"


@pytest.mark.parametrize("program", [
    "IF [[#1 GT 0] EQ 1] GOTO 10\nN10 M30\n",
    "#100 = [[#1 GT 0] EQ [#2 GT 0]]\nM30\n",
    "WHILE [[#3 LT -3] LT 1] DO1\nEND1\nM30\n",
], ids=["if", "assignment", "while"])
def test_a_comparison_of_a_symbolic_comparison_does_not_crash(program):
    result = check_text(program, "t.nc")
    assert result.dialect == "iso"


def test_a_comparison_with_a_vacant_logical_operand_does_not_crash():
    result = check_text("#100 = [[1 GT 0] OR #0] LT 1\nM30\n", "t.nc")
    assert result.dialect == "iso"


@pytest.mark.parametrize("program", [
    "G90 G0 X[#1 GT 0]\nG91 X1.\nM30\n",
    "S100 M3\nG90 G0 X[#1 GT 0] Y0.\nG2 X1. Y1. I1. J0. F100.\nM30\n",
], ids=["incremental", "arc"])
def test_an_axis_word_given_by_a_symbolic_comparison_does_not_crash(program):
    result = check_text(program, "t.nc")
    assert result.dialect == "iso"


# --------------------------------------------------------------------------- a long file of garbage


def test_a_long_file_of_syntax_errors_is_capped_per_rule_and_ends_fast(tmp_path, capsys):
    lines = ["O1000", "G21 G90"] + [f"~~ garbage line {number} @@" for number in range(20_000)] + ["M30"]
    path = tmp_path / "garbage.nc"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    started = time.perf_counter()
    code, out, _ = cli(capsys, "check", "--format", "json", path)
    assert time.perf_counter() - started < 30
    entry = json.loads(out)["files"][0]
    syntax = [d for d in entry["diagnostics"] if d["rule"] == "core.syntax"]
    assert len(syntax) == Settings().max_findings_per_rule
    assert len(syntax) + entry["truncated"]["core.syntax"] == 20_000
    assert (syntax[0]["line"], syntax[0]["column"]) == (3, 1)
    assert code == 1


def test_the_text_report_says_how_many_findings_were_not_shown(tmp_path, capsys):
    path = tmp_path / "garbage.nc"
    path.write_text("O1000\nG21 G90\n" + "".join(f"~ {n}\n" for n in range(300)) + "M30\n", encoding="utf-8")
    _, out, _ = cli(capsys, "check", path)
    assert "note: 100 more core.syntax findings not shown" in out


def test_a_long_line_of_garbage_is_read_in_bounded_time():
    started = time.perf_counter()
    result = check_text("G21 G90\n" + "X1.(" * 20_000 + "\nM30\n", "t.nc")
    assert time.perf_counter() - started < 10
    assert findings(result, "core.syntax")


def test_moderately_nested_brackets_are_read():
    result = check_text("#1=" + "[" * 100 + "1" + "]" * 100 + "\n#3000=#1\nM30\n", "t.nc")
    [alarm] = findings(result, "core.macro-alarm")
    assert "#3000=1" in alarm.message


LONG_SUM = "#1=" + "+".join(["1"] * 1000)  # one 2,000-character line
DEEP_BRACKETS = "#1=" + "[" * 500 + "1" + "]" * 500


@pytest.mark.parametrize("line", [LONG_SUM, DEEP_BRACKETS], ids=["long-sum", "deep-brackets"])
def test_a_very_long_expression_does_not_crash_the_checker(line):
    result = check_text(line + "\nM30\n", "t.nc")
    assert result.dialect == "iso"


def test_a_very_long_expression_gives_no_traceback_on_the_command_line(tmp_path, capsys):
    path = tmp_path / "long.nc"
    path.write_text(LONG_SUM + "\nM30\n", encoding="utf-8")
    code, _, _ = cli(capsys, "check", path)
    assert code in (0, 1)


def test_an_empty_file_is_not_a_program(tmp_path, capsys):
    path = tmp_path / "empty.nc"
    path.write_bytes(b"")
    code, out, err = cli(capsys, "check", path)
    assert code == 2
    assert "not checked" in out + err
