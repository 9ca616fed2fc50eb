"""The fast paths of HEIDENHAIN Klartext (CAM output runs through them block after block)
give exactly what the general ones give."""
from __future__ import annotations

from hypothesis import given, settings as hypothesis_settings, strategies as st

from ncverify.interpret.heidenhain.state import DrilledHoles
from ncverify.values import parameter

_COORDINATES = st.sampled_from([0.0, -0.0, 1.5, 2.0, float("nan"), parameter("QH1"), parameter("QH2")])
_HOLES = st.tuples(_COORDINATES, _COORDINATES, st.sampled_from([-5.0, -2.0, parameter("QH3")]))


@hypothesis_settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 30), _HOLES), max_size=30), _COORDINATES, _COORDINATES)
def test_drilled_holes_are_found_by_their_point_as_a_scan_of_all_finds_them(steps, x, y):
    """Each step adds a hole to one of the versions made so far (an older one: a forked
    path); every version finds at (x, y) what a scan of its own holes finds, in order."""
    versions, written = [DrilledHoles()], [[]]
    for pick, hole in steps:
        index = pick % len(versions)
        versions.append(versions[index].adding(*hole))
        written.append(written[index] + [hole])
    for holes, expected in zip(versions, written):
        assert list(holes) == expected and len(holes) == len(expected)
        assert holes.bottoms_at(x, y) == [bottom for hx, hy, bottom in expected if hx == x and hy == y]


_NUMBERS = st.sampled_from(["0", "5", "10.5", "1,5", ".5", "5.", "0.0", "007", "123456.789"])
_SIGNS = st.sampled_from(["", "+", "-"])
_AXIS_WORDS = st.builds("{}{}{}{}".format, st.sampled_from(["", "I"]), st.sampled_from(list("XYZABCUVW")), _SIGNS, _NUMBERS)
# words the fast path reads ...
_FAST_FORM_WORDS = st.one_of(
    _AXIS_WORDS, _AXIS_WORDS, _AXIS_WORDS,
    st.sampled_from(["R0", "RL", "RR", "FMAX", "F800", "F+5", "F0.5", "M3", "M5", "M8", "M9", "M30", "M91", "M99", "M89", "M140", "M136",
                     "M94", "DR+", "DR-", "R+6", "R6", "R-0", "R0.0", "R+0"]))
# ... and words it leaves to the general path (which may refuse them)
_OTHER_WORDS = st.sampled_from(["R", "F", "M", "FAUTO", "FU5", "FZ0.1", "F MAX", "F AUTO", "M+3", "M3.5", "M140 MB+10", "M140 MB MAX", "DR", "DR5",
                                "X+", "X", "RL5", "R00", "Q1", "X+Q1", "X+1E5", "x+1", "X+1,", "LEN+5", "PA+90", "X+1;cut", "X+5 ~", "/", "*"])


def _motion_line(number, function, words, gap, end):
    return f"{number}{function}" + "".join(gap + word for word in words) + end


_LINE_PARTS = (st.sampled_from(["", "7 ", "  12  ", "0\t", "3.5 ", "/5 "]), st.sampled_from(["L", "CC", "C", "CR", "CT", "LP", "Lx"]))
_GAPS, _ENDS = st.sampled_from([" ", "  ", "\t"]), st.sampled_from(["", " ", "\r", " \r"])


@hypothesis_settings(max_examples=1000, deadline=None)
@given(*_LINE_PARTS, st.lists(st.one_of(_FAST_FORM_WORDS, _FAST_FORM_WORDS, _OTHER_WORDS), max_size=6), _GAPS, _ENDS, st.sampled_from([None, "SUB.H"]))
def test_the_fast_motion_path_gives_the_general_paths_block_or_none(number, function, words, gap, end, path):
    from ncverify.lower.heidenhain import KlartextLowering

    raw = _motion_line(number, function, words, gap, end).encode()
    lowering = KlartextLowering()
    fast = lowering._fast_motion(raw, 7, path)
    assert fast is None or fast == lowering._general(raw, 7, path), raw


@hypothesis_settings(max_examples=500, deadline=None)
@given(st.sampled_from(["", "7 ", "  12  ", "0\t"]), st.sampled_from(["L", "CC", "C", "CR", "CT"]), st.lists(_FAST_FORM_WORDS, max_size=6), _GAPS, _ENDS)
def test_the_fast_motion_path_reads_every_line_of_its_form_the_general_path_accepts(number, function, words, gap, end):
    """Lines of the fast form (a plain block number, a path function, words apart by
    blanks): the fast path reads every one the general path reads without a syntax error."""
    from ncverify.lower.heidenhain import KlartextLowering

    raw = _motion_line(number, function, words, gap, end).encode()
    lowering = KlartextLowering()
    general = lowering._general(raw, 7, None)
    if not any(note.rule == "core.syntax" for note in general.notes):
        assert lowering._fast_motion(raw, 7, None) == general, raw
    else:
        assert lowering._fast_motion(raw, 7, None) is None, raw
