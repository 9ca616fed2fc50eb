"""Detection from the text alone: short programs whose only dialect evidence is a cycle call."""
from __future__ import annotations

import textwrap

import pytest
from hypothesis import given, settings as hypothesis_settings
from hypothesis import strategies as st

from ncverify import detect as detect_module
from ncverify.detect import detect

SHORT_SINUMERIK = {
    "modal drilling call": """
        T1 D1 M6
        S1000 M3
        G0 X0 Y0 Z50
        MCALL CYCLE81(10,0,2,-5)
        X10 Y10
        X20
        MCALL
        M30
        """,
    "one deep-hole call": """
        T2 D1 M6
        S800 M3
        G0 X40 Y25 Z20
        CYCLE83(10,0,1,-30,,-5,,3,0.5,1,1,0)
        G0 Z100
        M30
        """,
    "a pocket": """
        T3 D1 M6
        S2500 M3 G17 G90
        G0 X60 Y40 Z10
        POCKET3(5,0,1,-12,80,50,6,60,40,0,4,0.2,0.2,300,150,0,11,5)
        M30
        """,
}


@pytest.mark.parametrize("name", sorted(SHORT_SINUMERIK))
def test_a_short_program_with_a_sinumerik_cycle_call_is_sinumerik(name):
    text = textwrap.dedent(SHORT_SINUMERIK[name])
    assert detect(text, text.encode()).dialect == "sinumerik"


def test_a_fagor_modal_subroutine_call_is_not_taken_for_sinumerik_mcall():
    text = textwrap.dedent("""
        T1 D1 M6
        S1000 M3
        G0 X0 Y0 Z50
        #MCALL ["DRILL"] (P0=5)
        X10 Y10
        #MDOFF
        M30
        """)
    assert detect(text, text.encode()).dialect == "fagor"


def test_an_iso_program_with_plain_cycles_stays_iso():
    text = textwrap.dedent("""
        O1000
        T1 M6
        G90 G54 G0 X0 Y0 S1000 M3
        G43 H1 Z50.
        G81 X10. Y10. Z-5. R2. F100
        X20.
        G80
        M30
        """)
    assert detect(text, text.encode()).dialect == "iso"


LOWER_CASE_SINUMERIK = """\
proc SPACING(int holes, real pitch)
def int done
def string[40] note
if (holes<1)
  note="no holes asked for"
  setal(61002)
else
  done=holes*pitch
endif
ret
"""

PYTHON = """\
import math
from pathlib import Path

def spacing(holes, pitch):
    return holes * pitch
"""


def test_a_sinumerik_subprogram_in_lower_case_is_not_taken_for_python():
    """DEF and PROC are SINUMERIK keywords in either case; a Python definition ends with a colon."""
    assert detect(LOWER_CASE_SINUMERIK, suffix=".spf").dialect == "sinumerik"


def test_python_source_is_still_not_a_program():
    detection = detect(PYTHON, suffix=".spf")
    assert detection.dialect is None and "Python" in detection.reason


@hypothesis_settings(max_examples=300)
@given(st.binary(min_size=1, max_size=300).filter(lambda sample: b"\x00" not in sample))
def test_control_bytes_are_counted_as_one_by_one(sample):
    """Text is binary when over 5% of its bytes are control bytes other than tab, line
    ends, form feed and the DOS end mark (counted by deleting every other byte)."""
    control = sum(1 for byte in sample if byte < 32 and byte not in (9, 10, 12, 13, 26))
    assert detect_module._looks_binary(sample) == (control / len(sample) > 0.05)
