"""Messages speak the language of the program they are about, not ISO's."""
from __future__ import annotations

import textwrap

from ncverify import Settings, check_text


def messages(program: str, rule: str, dialect: str) -> list[str]:
    result = check_text(textwrap.dedent(program), settings=Settings(dialect=dialect, loop_bound=50))
    return [d.message for d in result.diagnostics if d.rule == rule]


def test_a_klartext_fn14_error_is_named_as_written():
    program = """
        0 BEGIN PGM ERR MM
        1 FN 14: ERROR = 1000
        2 END PGM ERR MM
        """
    [message] = messages(program, "core.macro-alarm", "heidenhain")
    assert "error number 1000 with FN 14: ERROR" in message
    assert "#3000" not in message


def test_an_endless_sinumerik_while_is_not_described_in_iso_words():
    program = """
        R1=0
        WHILE R1<5
        G1 X10 F100
        ENDWHILE
        M30
        """
    [message] = messages(program, "core.loop-bound", "sinumerik")
    assert message.startswith("the loop that ends here ran 50 times")
    assert "DO" not in message


MODAL_CALL_LEFT_ON = """
    T1 D1
    M6
    S1000 M3
    G0 X0 Y0 Z50
    MCALL CYCLE81(10,0,2,-5)
    X10 Y10
    T2 D1
    M6
    M30
    """


def test_a_sinumerik_modal_call_left_on_is_cancelled_with_mcall_not_g80():
    for rule in ("core.cycle-modal-at-tool-change", "core.cycle-modal-at-end"):
        [message] = messages(MODAL_CALL_LEFT_ON, rule, "sinumerik")
        assert "(no MCALL)" in message and "G80" not in message


def test_a_missing_feed_names_the_e60_alarm_only_on_the_e60():
    program = """
        O1
        G90 G0 X0 Y0 Z5 S1000 M3
        G1 Z-2
        M30
        """
    [e60] = messages(program, "core.feed-missing", "iso")
    assert "E60 alarm P62" in e60
    [fanuc] = [d.message for d in check_text(textwrap.dedent(program), settings=Settings(dialect="iso", profile="fanuc")).diagnostics
               if d.rule == "core.feed-missing"]
    [sinumerik] = messages("G90 G0 X0 Y0 Z5 S1000 M3\nG1 Z-2\nM30\n", "core.feed-missing", "sinumerik")
    assert "P62" not in fanuc and "P62" not in sinumerik


ROUNDED_DIVISOR = """
    0 BEGIN PGM STEPS MM
    1 Q1950 = Q1804 - Q1805
    2 Q1951 = INT ( ( Q1950 / 2 ) + 0.99999999 )
    3 Q1952 = Q1950 / Q1951
    4 END PGM STEPS MM
    """


def test_an_unknown_value_is_shown_by_what_it_came_from_not_by_its_internal_name():
    [message] = messages(ROUNDED_DIVISOR.replace("INT (", "SIN ("), "core.arithmetic-domain", "heidenhain")
    assert message.startswith("division by Q1951 = SIN(…), which can be zero")


def test_a_rounded_value_is_shown_with_its_argument():
    [message] = messages(ROUNDED_DIVISOR, "core.arithmetic-domain", "heidenhain")
    assert message.startswith("division by Q1951 = FIX(99999999/100000000 + 1/2*Q1804 + -1/2*Q1805), which can be zero")


def test_checking_a_program_twice_in_one_process_gives_the_same_findings_word_for_word():
    def findings():
        result = check_text(textwrap.dedent(ROUNDED_DIVISOR), settings=Settings(dialect="heidenhain"))
        return [(d.rule, d.span, d.status, d.message, d.reason) for d in result.diagnostics]

    assert findings() == findings()


def test_unknown_values_are_numbered_afresh_for_every_check():
    from ncverify import values

    def first_name():
        with values.fresh_numbering():
            return str(values.fresh("FIX").term)

    assert first_name() == first_name() == "FIX~1"


def test_a_branch_on_an_unknown_value_names_it_readably_when_the_path_limit_is_hit():
    program = """
        0 BEGIN PGM BRANCH MM
        1 Q10 = INT ( Q1 / 3 )
        2 FN 9: IF +Q10 EQU +0 GOTO LBL 1
        3 FN 9: IF +Q2 EQU +0 GOTO LBL 1
        4 LBL 1
        5 END PGM BRANCH MM
        """
    result = check_text(textwrap.dedent(program), settings=Settings(dialect="heidenhain", max_paths=1))
    [message] = [d.message for d in result.diagnostics if d.rule == "core.path-limit"][:1]
    assert "~" not in message


MODAL_SUBPROGRAM = {
    "sinumerik": ("t.mpf", "MCALL", """
        T1 D1
        M6
        S2000 M3
        G0 X0 Y0 Z50
        MCALL SPOT(2)
        X20 Y20
        {off}
        T2 D1
        M6
        M30
        """),
    "fagor": ("t.pim", "#MDOFF", """
        %L SPOT
        G1 G91 Z-2 F100
        G0 Z2
        G90
        #RET
        T1 D1 M6
        S2000 M3
        G0 X0 Y0 Z50
        #MCALL SPOT
        X20 Y20
        {off}
        T2 D1 M6
        M30
        """),
}


def _modal_subprogram_findings(dialect: str, switched_off: bool) -> dict[str, list[str]]:
    name, off, program = MODAL_SUBPROGRAM[dialect]
    text = textwrap.dedent(program.format(off=off if switched_off else "")).lstrip("\n")
    result = check_text(text, name, Settings(dialect=dialect))
    rules = ("core.cycle-modal-at-tool-change", "core.cycle-modal-at-end")
    return {rule: [d.message for d in result.diagnostics if d.rule == rule] for rule in rules}


def test_a_modal_subprogram_call_left_on_at_the_tool_change_and_the_end_is_reported_in_the_controls_words():
    for dialect, (_name, off, _program) in MODAL_SUBPROGRAM.items():
        found = _modal_subprogram_findings(dialect, switched_off=False)
        assert [len(messages) for messages in found.values()] == [1, 1], (dialect, found)
        assert all("the modal call of SPOT is still active" in messages[0] and f"(no {off})" in messages[0] for messages in found.values())


def test_a_modal_subprogram_call_switched_off_before_the_tool_change_is_not():
    for dialect in MODAL_SUBPROGRAM:
        assert _modal_subprogram_findings(dialect, switched_off=True) == {"core.cycle-modal-at-tool-change": [], "core.cycle-modal-at-end": []}
