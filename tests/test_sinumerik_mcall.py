"""SINUMERIK ``MCALL NAME(...)``: the subprogram runs after every later block with a path
motion until a bare ``MCALL`` (seed A L4317-4364), and may not contain an MCALL of its own."""
from __future__ import annotations

import textwrap

from ncverify import Settings, check_text
from ncverify.diagnostics import Status
from ncverify.lower.sinumerik import SinumerikFrontend, SinumerikLowering

_DIVE = """
    %_N_DIVE_SPF
    PROC DIVE(REAL DEPTH)
    G0 Z=DEPTH
    G0 Z20
    M17
"""


def _check(program: str):
    return check_text(textwrap.dedent(program).lstrip("\n"), "t.mpf", Settings(dialect="sinumerik"))


def _crashes(result) -> list[str]:
    return [d.message for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.status is Status.VIOLATED]


def _main(calls: str) -> str:
    return """
        %_N_MAIN_MPF
        WORKPIECE(,"",,"BOX",0,0,-30,-80,0,0,80,60)
        G17 G90 G54 T2 D1 M6
        S3000 M3 F400
        G0 X10 Y10 Z20
    """ + textwrap.indent(textwrap.dedent(calls), "        ") + "        M30\n" + _DIVE


def test_the_modal_subprogram_runs_after_every_move_with_its_arguments_until_mcall_alone():
    result = _check(_main("""
        MCALL DIVE(-4)
        G0 X20
        G1 X30
        MCALL
        G0 X40
    """))
    plunges = [message for message in _crashes(result) if "to X" in message and "Z-4 passes" in message]
    assert [message.split(" to ")[1].split(" passes")[0] for message in plunges] == ["X20 Y10 Z-4", "X30 Y10 Z-4"]
    assert not any("X40" in message or "X10 Y10 Z-4" in message for message in _crashes(result))


def test_a_later_mcall_replaces_the_arguments_and_a_cycle_mcall_ends_the_subprogram_call():
    result = _check(_main("""
        MCALL DIVE(-4)
        G0 X20
        MCALL DIVE(5)
        G0 X30
        MCALL CYCLE81(20, 0, 2, -2)
        G0 X40 Y10
        MCALL
    """))
    crashes = _crashes(result)
    assert any("to X20 Y10 Z-4 passes" in message for message in crashes)
    assert not any("X30" in message or "X40 Y10 Z-4" in message for message in crashes)


def test_without_mcall_the_subprogram_is_only_a_subprogram():
    result = _check(_main("""
        G0 X20
        G1 X30
    """))
    assert _crashes(result) == []


def test_an_mcall_inside_the_modally_called_subprogram_is_reported():
    result = _check("""
        %_N_MAIN_MPF
        G17 G90 G54 T1 D1 M6
        S1200 M3 F150
        G0 X0 Y0 Z20
        MCALL SPOT(2)
        G0 X10 Y10
        MCALL
        SPOT(2)
        M30
        %_N_SPOT_SPF
        PROC SPOT(REAL DEPTH)
        MCALL CYCLE81(10, 0, 2, -DEPTH)
        G0 X0
        MCALL
        M17
    """)
    [nested] = [d for d in result.diagnostics if d.rule == "sinumerik.nested-mcall"]
    assert nested.status is Status.VIOLATED and nested.span.line == 12
    assert "MCALL CYCLE81" in nested.message and "cannot nest" in nested.message


def test_no_batch_of_plain_moves_once_a_subprogram_may_be_called_modally():
    cycle_only, with_subprogram = SinumerikFrontend(SinumerikLowering()), SinumerikFrontend(SinumerikLowering())
    cycle_only.programs(b"MCALL CYCLE81(10, 0, 2, -8)\nG0 X10\nMCALL\nM30\n")
    with_subprogram.programs(b"N10 MCALL DIVE(-4, 2)\nG0 X10\nMCALL\nM30\n")
    assert cycle_only.is_plain(b"G0 X10") and not with_subprogram.is_plain(b"G0 X10")
    assert with_subprogram.plain_run(b"G0 X10\nG0 X20\n", 0, 1) is None
    assert with_subprogram.lowering.modal_call_arity == 2


def test_the_arguments_are_the_values_when_the_call_was_switched_on():
    result = _check(_main("""
        R7 = -4
        MCALL DIVE(R7)
        R7 = 5
        G0 X20
        MCALL
    """))
    assert any("to X20 Y10 Z-4 passes" in message for message in _crashes(result))


def test_the_modal_call_forks_with_the_path():
    """Switched off on one branch of an unknown condition, it still runs on the other (and
    switched on on one, it runs there)."""
    switched_off_on_one_branch = _check(_main("""
        MCALL DIVE(-4)
        IF R5 > 0
          MCALL
        ENDIF
        G0 X20
        MCALL
    """))
    switched_on_on_one_branch = _check(_main("""
        IF R5 > 0
          MCALL DIVE(-4)
        ENDIF
        G0 X20
        MCALL
    """))
    for result in (switched_off_on_one_branch, switched_on_on_one_branch):
        assert any("to X20 Y10 Z-4 passes" in message for message in _crashes(result))
