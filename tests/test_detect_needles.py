"""Detection skips a pattern none of whose needles (literal text every match contains) is in
the text, and counts a pattern's matches only up to three. Both must leave every detection
as running every pattern in full gives it."""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from ncverify import detect as detection
from ncverify.detect import _Head, _detect

ROOT = Path(__file__).resolve().parent.parent
_CORPORA = [ROOT / "corpus", ROOT.parent / "shared" / "corpus-realworld"]


def _patterns() -> list[tuple[str, str]]:
    """Every (pattern, needles) pair detection runs."""
    pairs = [(pattern, needles) for signatures in detection._SIGNATURES.values() for pattern, _, needles in signatures]
    pairs += [(pattern, needles) for pattern, _, needles in detection._NOT_A_PROGRAM]
    pairs += [(pattern, needles) for _, signals in detection._LOOKALIKES for pattern, _, needles in signals]
    pairs += [(pattern, needles) for pattern, _, needles in detection._LATHE + detection._MILL]
    pairs += [detection._HAAS, detection._FANUC_LATHE, detection._MITSUBISHI]
    return pairs


_NEEDLES = sorted({needle for _, needles in _patterns() for needle in needles.split("|")})
# Text built from the needles themselves, cut into pieces and in lower case too, with the
# digits, signs, brackets and blanks the patterns look for around them.
_FRAGMENTS = st.one_of(
    st.sampled_from(_NEEDLES),
    st.sampled_from(_NEEDLES).map(str.lower),
    st.sampled_from(_NEEDLES).flatmap(lambda needle: st.integers(0, len(needle)).map(lambda cut: needle[:cut])),
    st.sampled_from(list("GMTXYZUWIJKRPQDENHLOSFV0123456789.-+=#$%_:;,()[]<>\"/ \t\r\n") + ["\n", "\n", " ", "\f", "\v"]),
)
_TEXT = st.lists(_FRAGMENTS, max_size=60).map("".join)


def _general(text: str, suffix: str = ""):
    return _detect(_Head(text, skip_by_needles=False), b"", suffix)


@settings(max_examples=400, suppress_health_check=[HealthCheck.too_slow])
@given(_TEXT)
@example("O1000\nG21 G90\nT1 M6\nIF [#1 GT 2] GOTO 10\nG1 X1. Y2.\nM30\n")
@example("DEF REAL A\nCYCLE81(1,2)\nM17\n")
def test_every_match_of_a_pattern_holds_one_of_its_needles(text):
    upper = text.upper()
    for pattern, needles in _patterns():
        for match in re.finditer(pattern, text):
            assert any(needle in match.group(0).upper() for needle in needles.split("|")), (pattern, match.group(0))
            assert any(needle in upper for needle in needles.split("|"))


@settings(max_examples=300, suppress_health_check=[HealthCheck.too_slow])
@given(_TEXT, st.sampled_from(["", ".nc", ".mpf", ".h", ".pim"]))
def test_detection_with_needles_is_detection_without(text, suffix):
    assert detection.detect(text, b"", suffix) == _general(text, suffix)


@pytest.mark.parametrize("folder", _CORPORA, ids=["corpus", "corpus-realworld"])
def test_every_corpus_program_is_detected_as_without_needles(folder):
    if not folder.is_dir():
        pytest.skip(f"{folder} is not here")
    files = [path for path in sorted(folder.rglob("*")) if path.is_file()]
    assert files
    for path in files:
        head = path.read_bytes()[:65536].decode("utf-8", errors="replace")
        assert detection.detect(head, b"", path.suffix) == _general(head, path.suffix), path


def test_a_text_outside_ascii_runs_every_pattern():
    """Case rules beyond ASCII are wider than upper-casing (the Kelvin sign is a K to
    IGNORECASE), so such text is never skipped by its needles."""
    text = "T1 M6\n\u212a\nTOOL CALL 1 Z S3000\nCYCL DEF 200\nBLK FORM 0.1 Z\n"
    assert _Head(text).upper is None
    assert detection.detect(text) == _general(text)
    assert detection.detect(text).dialect == "heidenhain"


def test_only_three_matches_of_a_pattern_count():
    many = "G1 X1. Y1.\n" * 50
    assert _Head(many).count(r"(?im)(?<![A-Z])[GM]\d+", "G|M") == 3
    assert _Head(many).count(r"(?im)\bM98\s*P", "M98") == 0
    assert len(re.findall(r"(?im)(?<![A-Z])[GM]\d+", many)) == 50


_CASELESS = [pattern for pattern, _ in _patterns() if detection._IGNORES_CASE.match(pattern)]


def _same_matches_in_upper_form(text: str) -> None:
    upper = text.upper()
    for pattern in _CASELESS:
        expected = [match.span() for match in re.finditer(pattern, text)]
        assert [match.span() for match in detection._upper_form(pattern).finditer(upper)] == expected, (pattern, text)


@settings(max_examples=400, suppress_health_check=[HealthCheck.too_slow])
@given(_TEXT)
@example("g1x1. m6 t0101 G17 xg17 (print, a) V.A.B #<x> IF[1] Millmaster")
def test_a_caseless_pattern_in_its_upper_case_form_matches_alike(text):
    """Every pattern that ignores case finds, in its upper-case form on the upper-cased
    text, the same matches at the same places as itself on the text."""
    _same_matches_in_upper_form(text)


@pytest.mark.parametrize("folder", _CORPORA, ids=["corpus", "corpus-realworld"])
def test_caseless_patterns_match_corpus_heads_alike_in_upper_case_form(folder):
    if not folder.is_dir():
        pytest.skip(f"{folder} is not here")
    for path in sorted(folder.rglob("*")):
        head = path.read_bytes()[:65536].decode("utf-8", errors="replace") if path.is_file() else ""
        if head.isascii():
            _same_matches_in_upper_form(head)


_WORDS_AS_WRITTEN_BEFORE = {detection._INTEGER_LENGTH: r"(?<![A-Z#\[])[XYZUWIJKR][ \t]*-?(\d+)(?![\d.])",
                            detection._POINT_LENGTH: r"(?<![A-Z#\[])[XYZUWIJKR][ \t]*-?\d*\.\d*"}


@settings(max_examples=300, suppress_health_check=[HealthCheck.too_slow])
@given(_TEXT)
@example("X5 [X5 #X5 AX5 X-12 Y.5 1X5")
def test_the_word_patterns_with_the_letter_first_match_as_before(text):
    """Whether integers mean whole units is read with the look-behind after the letter."""
    code = text.upper()
    for pattern, before in _WORDS_AS_WRITTEN_BEFORE.items():
        assert [(match.span(), match.groups()) for match in pattern.finditer(code)] == [
            (match.span(), match.groups()) for match in re.finditer(before, code)]


def test_the_upper_case_form_opens_with_the_letter():
    """The leading boundary or look-behind is moved behind the literal text that follows
    it (what makes the form fast); a boundary before anything but letters stays where it is."""
    assert detection._upper_form(r"(?im)\bM(?:30|0?2)").pattern == r"(?m)M(?<!\wM)(?:30|0?2)"
    assert detection._upper_form(r"(?im)\bm6[2-8]").pattern == r"(?m)M6(?<!\wM6)[2-8]"
    assert detection._upper_form(r"(?im)(?<![A-Z])[gm]\d+").pattern == r"(?m)[GM](?<![A-Z][GM])\d+"
    assert detection._upper_form(r"(?i)\b[(#]x").pattern == r"\b[(#]X"
    assert detection._upper_form(r"(?i)\bG10?1").pattern == r"G1(?<!\wG1)0?1"
    assert detection._upper_form(r"(?i)\bG?1").pattern == r"\bG?1"
