"""The ISO reader: text to blocks of words, statements and comments, and the two paths
(regex fast path, lark grammar) that must read plain blocks the same way."""
from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ncverify import Settings, check_text, ir
from ncverify.lower.iso import IsoFrontend, IsoLowering
from ncverify.read.iso import Statement, Word, read_line
from ncverify.tables import iso_table


def _words(text: str) -> list[tuple[str, object, bool]]:
    [block] = read_line(text, 1)
    assert block.problem is None, block.problem
    return [(item.letter, item.value, item.has_point) for item in block.items if isinstance(item, Word)]


def _statement(text: str) -> Statement:
    [block] = read_line(text, 1)
    assert block.problem is None, block.problem
    [statement] = [item for item in block.items if isinstance(item, Statement)]
    return statement


def _problem(text: str):
    problems = [block.problem for block in read_line(text, 1) if block.problem is not None]
    assert len(problems) == 1, problems
    return problems[0]


# --------------------------------------------------------------------------- blocks and words


def test_a_plain_block_reads_as_its_words_in_order():
    assert _words("N10 G01 X10.5 Y-3 F800.") == [
        ("N", 10.0, False), ("G", 1.0, False), ("X", 10.5, True), ("Y", -3.0, False), ("F", 800.0, True),
    ]


def test_word_columns_are_zero_based_and_end_exclusive():
    [block] = read_line("  G1 X10.5", 1)
    g, x = block.items
    assert (g.start, g.end) == (2, 4)
    assert (x.start, x.end) == (5, 10)
    assert (block.start, block.end) == (2, 10)


def test_lower_case_letters_read_like_upper_case():
    assert _words("n5 g1 x2. f100") == _words("N5 G1 X2. F100")


def test_spaces_between_letter_and_number_are_ignored():
    assert _words("G 1 X 10. Y  -2.5") == [("G", 1.0, False), ("X", 10.0, True), ("Y", -2.5, True)]


def test_the_n_number_is_read_as_a_word():
    assert _words("N0123 G0 X1.")[0] == ("N", 123.0, False)


def test_a_word_with_a_decimal_point_is_marked_and_one_without_is_not():
    assert _words("X10. Y10 Z.5 A-1.") == [("X", 10.0, True), ("Y", 10.0, False), ("Z", 0.5, True), ("A", -1.0, True)]


def test_a_slash_at_the_start_makes_the_block_skippable():
    [block] = read_line("/N20 G0 X1.", 1)
    assert block.skip is True
    assert [item.letter for item in block.items] == ["N", "G", "X"]


def test_a_block_without_a_slash_is_not_skippable():
    [block] = read_line("N20 G0 X1.", 1)
    assert block.skip is False


def test_a_skippable_block_is_skippable_in_the_ir_too():
    frontend = _frontend("mitsubishi-e60", "mill")
    [block] = frontend.blocks(b"/G0 X1.", 1, None)
    assert block.skippable is True


def test_comments_before_between_and_after_words_are_collected_with_their_text():
    [block] = read_line("(START) G1 (MOVE) X10. (END)", 1)
    assert [text for text, _, _ in block.comments] == ["START", "MOVE", "END"]
    assert [(item.letter, item.value) for item in block.items] == [("G", 1.0), ("X", 10.0)]


def test_a_chinese_comment_is_kept_and_columns_count_characters_not_bytes():
    [block] = read_line("(加工 中心) G1 X10.", 1)
    assert block.comments[0][0] == "加工 中心"
    g, x = block.items
    assert (g.start, x.start) == (8, 11)


def test_a_line_that_is_only_a_comment_has_no_words():
    [block] = read_line("(T1 D10 端铣刀)", 1)
    assert block.items == []
    assert block.comments[0][0] == "T1 D10 端铣刀"


def test_a_semicolon_ends_a_block_so_one_line_holds_two_blocks():
    first, second = read_line("G1 X1.; G0 Y2.", 7)
    assert [(w.letter, w.value) for w in first.items] == [("G", 1.0), ("X", 1.0)]
    assert [(w.letter, w.value) for w in second.items] == [("G", 0.0), ("Y", 2.0)]
    assert first.line == second.line == 7
    assert (second.start, second.end) == (8, 14)


def test_a_semicolon_inside_a_comment_does_not_end_the_block():
    blocks = read_line("G1 X1. (A;B) Y2.", 1)
    assert len(blocks) == 1
    assert [w.letter for w in blocks[0].items] == ["G", "X", "Y"]


def test_a_trailing_semicolon_makes_no_empty_block():
    assert len(read_line("G0 X1.;", 1)) == 1


def test_a_percent_line_is_a_tape_mark():
    [block] = read_line("%", 1)
    assert block.percent is True
    assert block.items == []


def test_text_between_the_tape_marks_is_checked():
    result = check_text("%\nO1000\nG21 G90 G0 X1.\nG1 X1. F0. 5\nM30\n%\n", "t.nc")
    assert [d.span.line for d in result.diagnostics if d.rule == "core.syntax"] == [4]


def test_text_after_the_closing_tape_mark_is_not_read():
    result = check_text("%\nO1000\nG21 G90 G0 X1.\nM30\n%\nG1 X1. F0. 5\n", "t.nc")
    assert "core.syntax" not in {d.rule for d in result.diagnostics}


def test_an_empty_line_has_no_blocks():
    assert read_line("", 1) == []
    assert read_line("   \t ", 1) == []


def test_an_o_number_is_read_as_a_word():
    assert _words("O1234") == [("O", 1234.0, False)]


def test_an_o_number_starts_a_program_in_the_ir():
    [block] = _frontend("mitsubishi-e60", "mill").blocks(b"O1234 (MAIN)", 1, None)
    assert block.program_start == "O1234"


def test_a_comma_word_is_read_with_its_comma():
    assert _words("G1 X10. ,R1") == [("G", 1.0, False), ("X", 10.0, True), (",R", 1.0, False)]
    assert _words(",C0.5") == [(",C", 0.5, True)]


def test_a_bare_g_is_a_word_without_a_value():
    assert _words("G X10.") == [("G", None, False), ("X", 10.0, True)]


def test_a_bare_g_is_reported_as_a_rapid():
    result = check_text("G X10.\nM30\n", "t.nc")
    bare = [d for d in result.diagnostics if d.rule == "core.bare-g"]
    assert len(bare) == 1 and (bare[0].span.line, bare[0].span.column) == (1, 1)


# --------------------------------------------------------------------------- macro statements


def test_an_assignment_with_brackets_and_a_function():
    statement = _statement("#1=[#2+3]*SIN[30]")
    assert statement.kind == "assign"
    assert statement.target.name == "#1"
    assert statement.value == ir.Binary("*", ir.Binary("+", ir.Var("#2", statement.value.left.left.span), 3.0), ir.Func("SIN", (30.0,)))


def test_a_variable_in_an_expression_carries_its_columns():
    statement = _statement("#1=[#2+3]*SIN[30]")
    variable = statement.value.left.left
    assert (variable.span.column, variable.span.end_column) == (5, 7)


def test_an_if_goto_reads_its_condition_and_target():
    statement = _statement("IF [#1 LT #2] GOTO 10")
    assert statement.kind == "if_goto"
    assert statement.condition.op == "LT"
    assert (statement.condition.left.name, statement.condition.right.name) == ("#1", "#2")
    assert statement.value == 10.0


def test_an_if_then_reads_its_condition_and_assignment():
    statement = _statement("IF [#1 GT 0] THEN #3=1")
    assert statement.kind == "if_then"
    assert statement.condition.op == "GT"
    assert statement.target.name == "#3"
    assert statement.value == 1.0


def test_a_while_loop_head_reads_its_condition_and_number():
    statement = _statement("WHILE [#1 LE 5] DO1")
    assert statement.kind == "while"
    assert statement.number == 1
    assert statement.condition.op == "LE"


def test_a_loop_end_reads_its_number():
    statement = _statement("END1")
    assert statement.kind == "end" and statement.number == 1


def test_a_goto_to_a_variable():
    statement = _statement("GOTO#22")
    assert statement.kind == "goto"
    assert statement.value.name == "#22"


def test_a_g_code_given_by_a_variable():
    [block] = read_line("G#3 X1.", 1)
    g, x = block.items
    assert g.letter == "G" and isinstance(g.value, ir.Var) and g.value.name == "#3"
    assert (x.letter, x.value) == ("X", 1.0)


def test_a_word_may_take_an_expression_in_brackets():
    [block] = read_line("G1 X[#1+2.] F100.", 1)
    x = block.items[1]
    assert x.letter == "X" and x.value == ir.Binary("+", ir.Var("#1", x.value.left.span), 2.0)


def test_a_negated_variable_word():
    [block] = read_line("X-#5", 1)
    [x] = block.items
    assert isinstance(x.value, ir.Unary) and x.value.op == "-" and x.value.operand.name == "#5"


def test_an_alarm_assignment_takes_its_message_from_the_comment():
    [block] = _frontend("mitsubishi-e60", "mill").blocks(b"#3000=1 (TOOL BROKEN)", 1, None)
    [alarm] = block.ops
    assert isinstance(alarm, ir.Alarm)
    assert alarm.message == "TOOL BROKEN"


# --------------------------------------------------------------------------- syntax errors


def test_an_unclosed_comment_is_a_syntax_problem_at_the_parenthesis():
    problem = _problem("G1 X1. (ROUGH")
    assert problem.start == 7
    assert "comment" in problem.message


def test_a_closing_parenthesis_without_an_opening_one_is_a_syntax_problem():
    problem = _problem("G1 X1.) Y2.")
    assert problem.start == 6


def test_a_space_inside_a_number_is_a_syntax_problem_at_the_stray_digit():
    problem = _problem("G1 X1. F0. 5")
    assert (problem.start, problem.end) == (11, 12)
    assert "address letter" in problem.message


def test_a_number_with_two_decimal_points_is_a_syntax_problem_at_the_second_point():
    problem = _problem("G2 X1. R20.616.")
    assert problem.start == 14


def test_a_non_ascii_character_outside_a_comment_is_a_syntax_problem_at_its_column():
    problem = _problem("G1 X1. é")
    assert (problem.start, problem.end) == (7, 8)
    assert "U+00E9" in problem.message


def test_chinese_text_outside_a_comment_is_a_syntax_problem_at_its_column():
    problem = _problem("G1 X中")
    assert problem.start == 4


def test_a_syntax_error_is_reported_at_the_exact_one_based_column():
    result = check_text("G21 G90\n(精加工) G1 X1. F0. 5\nM30\n", "t.nc")
    [syntax] = [d for d in result.diagnostics if d.rule == "core.syntax"]
    assert (syntax.span.line, syntax.span.column, syntax.span.end_column) == (2, 18, 19)


def test_an_unclosed_bracket_is_a_syntax_problem_from_the_bracket_to_the_end_of_the_block():
    problem = _problem("#1=[#2+3")
    assert (problem.start, problem.end) == (3, 8)


@pytest.mark.parametrize("text", ["#1=[#2+3", "G1 X[#1", "#1=SIN[30"])
def test_an_unclosed_bracket_is_not_blamed_on_a_space_inside_a_number(text):
    problem = _problem(text)
    assert "space inside a number" not in problem.message


def test_a_syntax_problem_in_one_block_leaves_the_other_block_of_the_line_alone():
    first, second = read_line("G1 X1. F0. 5; G0 Y2.", 1)
    assert first.problem is not None
    assert second.problem is None and [w.letter for w in second.items] == ["G", "Y"]


# --------------------------------------------------------------------------- fast path and grammar agree

PROFILES_AND_MACHINES = [(profile, machine) for profile in ("mitsubishi-e60", "haas") for machine in ("mill", "lathe")]


def _frontend(profile: str, machine: str) -> IsoFrontend:
    return IsoFrontend(IsoLowering(iso_table(profile, machine)))


FRONTENDS = {key: _frontend(*key) for key in PROFILES_AND_MACHINES}

_digits = st.integers(min_value=0, max_value=99999).map(str)


@st.composite
def numbers(draw) -> str:
    """A number as CAM output writes it: integer, with a trailing point, with a fraction,
    a leading point, with or without a sign and leading zeros."""
    sign = draw(st.sampled_from(["", "-", "+"]))
    whole = draw(_digits)
    fraction = draw(st.integers(min_value=0, max_value=9999).map(str))
    form = draw(st.sampled_from(["int", "point", "fraction", "leading", "zeros"]))
    body = {"int": whole, "point": whole + ".", "fraction": f"{whole}.{fraction}", "leading": "." + fraction, "zeros": "00" + whole}[form]
    return sign + body


_space = st.sampled_from(["", " ", "  ", "\t"])


@st.composite
def plain_blocks(draw) -> tuple[str, list[tuple[str, str]]]:
    """A plain block (optional N, optional G0-G3, X/Y/Z/F and arc centre or radius words
    I/J/K/R once each) in random order and spacing; returns the text and the (letter,
    number text) pairs written."""
    words: list[tuple[str, str]] = []
    if draw(st.booleans()):
        words.append(("N", draw(_digits)))
    if draw(st.booleans()):
        words.append(("G", draw(st.sampled_from(["0", "1", "2", "3", "00", "01", "02", "03"]))))
    for letter in draw(st.lists(st.sampled_from("XYZFIJKR"), unique=True, max_size=6)):
        words.append((letter, draw(numbers())))
    if not words:
        words.append(("X", draw(numbers())))
    words = draw(st.permutations(words))
    parts = [draw(_space)]
    for index, (letter, number) in enumerate(words):
        if index:
            parts.append(draw(_space))
        parts.append(letter + draw(st.sampled_from(["", "", " "])) + number)
    parts.append(draw(_space))
    text = "".join(parts)
    return text, words


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(block=plain_blocks(), key=st.sampled_from(PROFILES_AND_MACHINES), line=st.integers(min_value=1, max_value=10**6))
def test_the_fast_path_and_the_grammar_lower_a_plain_block_to_equal_ir(block, key, line):
    text, _ = block
    frontend = FRONTENDS[key]
    fast = frontend.blocks(text.encode("ascii"), line, None)
    grammar = [frontend.lowering.lower(read, None) for read in read_line(text, line, force_grammar=True)]
    assert fast == grammar


@settings(max_examples=150, deadline=None)
@given(block=plain_blocks(), key=st.sampled_from(PROFILES_AND_MACHINES))
def test_lower_case_plain_blocks_lower_like_upper_case_ones(block, key):
    text, _ = block
    frontend = FRONTENDS[key]
    assert frontend.blocks(text.lower().encode(), 3, None) == frontend.blocks(text.upper().encode(), 3, None)


def _lower_both_ways(text: str, key=("mitsubishi-e60", "mill")):
    frontend = FRONTENDS[key]
    fast = frontend.blocks(text.encode("ascii"), 1, None)
    grammar = [frontend.lowering.lower(read, None) for read in read_line(text, 1, force_grammar=True)]
    return fast, grammar


@pytest.mark.parametrize("text", ["N12 G2 X10. Y5. I-5. J0. F800.", "G03 X1.5 Y2. Z-1. I0.5 J.5", "X3. Y4. R5.", "Y4. R-5. X3. G2"])
def test_arcs_with_centre_or_radius_words_take_the_fast_path(text):
    fast = FRONTENDS[("mitsubishi-e60", "mill")]._plain_motion(text.encode("ascii"), 1, None)
    assert fast is not None
    assert [fast] == _lower_both_ways(text)[1]


@pytest.mark.parametrize("text", ["G1 X1. I2.", "G0 X1. R3.", "G2 X1. I1. I2."])
def test_centre_words_on_a_straight_move_or_twice_leave_the_fast_path(text):
    assert FRONTENDS[("mitsubishi-e60", "mill")]._plain_motion(text.encode("ascii"), 1, None) is None


@pytest.mark.parametrize("text", ["G1 X1. X2.", "G0 G1 X1.", "N1 N2 X1.", "G1 X1 Y2 Z3 A4 B5 C6 F7"])
def test_blocks_the_fast_path_hands_back_lower_like_the_grammar(text):
    fast, grammar = _lower_both_ways(text)
    assert fast == grammar


def test_a_block_with_two_f_words_lowers_the_same_on_both_paths():
    fast, grammar = _lower_both_ways("G1 X10. F100. F200.")
    assert fast == grammar


def test_two_feed_words_in_a_block_are_a_duplicate_address():
    result = check_text("G21 G90\nG1 X10. F100. F200.\nM30\n", "t.nc")
    assert "core.duplicate-address" in {d.rule for d in result.diagnostics}


def test_two_feed_words_in_a_lower_case_block_are_a_duplicate_address():
    result = check_text("g21 g90\ng1 x10. f100. f200.\nm30\n", "t.nc")
    assert "core.duplicate-address" in {d.rule for d in result.diagnostics}


# --------------------------------------------------------------------------- never raises


@settings(max_examples=300, deadline=None)
@given(text=st.text())
def test_read_line_never_raises_on_any_text(text):
    for line in text.splitlines() or [text]:
        for block in read_line(line, 1):
            assert 0 <= block.start <= block.end <= max(len(line), 1)


_NC_PIECES = st.sampled_from([
    "G", "X", "Y", "Z", "N", "M", "F", "R", "P", "L", "Q", "O", "#", "[", "]", "=", "(", ")", "/", ";", ",", "%",
    "0", "1", "5", ".", "-", "+", " ", "\n", "IF", "GOTO", "WHILE", "DO1", "END1", "THEN", "EQ", "LT", "SIN",
    "M98", "M99", "G65", "G81", "G91", "#1", "#100", "中", "\x00", "\r",
])


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=st.one_of(st.text(max_size=200), st.lists(_NC_PIECES, max_size=80).map("".join)))
def test_check_text_never_raises_on_any_text(text):
    result = check_text(text, "fuzz.nc", Settings(loop_bound=50))
    for diagnostic in result.diagnostics:
        assert diagnostic.span.line >= 1 and diagnostic.span.column >= 1


# --------------------------------------------------------------------------- round trip


@settings(max_examples=300, deadline=None)
@given(block=plain_blocks())
def test_the_numbers_read_back_equal_the_numbers_written(block):
    text, written = block
    [read] = read_line(text, 1)
    assert read.problem is None
    got = [(word.letter, word.value, word.has_point) for word in read.items]
    assert got == [(letter, float(number), "." in number) for letter, number in written]


@settings(max_examples=200, deadline=None)
@given(block=plain_blocks())
def test_each_word_s_columns_hold_exactly_its_text(block):
    text, written = block
    [read] = read_line(text, 1)
    for word, (letter, number) in zip(read.items, written):
        assert text[word.start : word.end].replace(" ", "").replace("\t", "") == letter + number
