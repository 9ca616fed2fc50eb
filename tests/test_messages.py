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
