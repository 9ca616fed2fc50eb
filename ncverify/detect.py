"""Which language a text is in, told from the text alone, with a confidence.

Each dialect has signature patterns with weights (data below: regexes over the first
64 KiB), each with its needles: literal text, in upper case, one of which every match
contains ("A|B": A or B). A pattern whose needles are all absent is not run (see
:class:`_Head`); only the first three matches of a pattern count, so its scan stops there. The best score wins; the confidence is its share of all scores, lowered when
little evidence was found. Texts that are not CNC programs at all (binary data, C or
Python source) are recognised so that a directory walk can skip them with a note.
"""
from __future__ import annotations

import functools
import itertools
import re
from dataclasses import dataclass

import numpy

_SIGNATURES: dict[str, list[tuple[str, float, str]]] = {
    "heidenhain": [
        (r"(?im)^\s*\d*\s*BEGIN\s+PGM\b", 8, "BEGIN"), (r"(?im)^\s*\d*\s*END\s+PGM\b", 6, "PGM"), (r"(?im)\bTOOL\s+CALL\b", 4, "TOOL"),
        (r"(?im)\bCYCL\s+DEF\b", 4, "CYCL"), (r"(?im)\bBLK\s+FORM\b", 4, "BLK"), (r"(?im)^\s*\d+\s+L\s+[XYZIR]", 2, "L"),
        (r"(?im)\bFMAX\b", 2, "FMAX"), (r"(?im)\bLBL\s+\d", 2, "LBL"), (r"(?im)\bFN\s+\d+\s*:", 2, "FN"),
    ],
    "sinumerik": [
        # a cycle called with its arguments in parentheses cannot be ISO, so one such call outweighs a short program's G/M words
        (r"(?im)^%_N_\w+_(?:MPF|SPF)", 30, "%_N_"), (r"(?im)\bCYCLE\d{2,3}\s*\(", 12, "CYCLE"), (r"(?im)(?<!#)\bMCALL[ \t]+\w+\s*\(", 8, "MCALL"), (r"(?im)\bDEF\s+(?:REAL|INT|BOOL|STRING|CHAR|AXIS|FRAME)\b", 4, "DEF"),
        (r"(?im)\bGOTO[FB]\b", 6, "GOTO"), (r"(?im)\bMSG\s*\(", 3, "MSG"), (r"(?im)\bWORKPIECE\s*\(", 10, "WORKPIECE"), (r"(?im)\$TC_DP", 3, "$TC_DP"),
        (r"(?im)\bT\s*=\s*\"", 3, '"'), (r"(?im)\b(?:ENDIF|ENDWHILE|ENDFOR|ENDLOOP)\b", 3, "END"), (r"(?im)\bCR\s*=", 2, "CR"),
        (r"(?im)\b(?:POCKET[1-4]|SLOT[12]|LONGHOLE|HOLES[12])\s*\(", 12, "POCKET|SLOT|LONGHOLE|HOLES"), (r"(?im)\bM17\b", 1, "M17"), (r"(?im)\b(?:AC|IC)\s*\(", 2, "AC|IC"),
        (r"(?im)^\s*(?:N\d+\s*)?PROC\s+\w+", 15, "PROC"), (r"(?im)\bR\d+\s*=", 3, "="), (r"(?im)\b[XYZ]\s*=\s*[-A-Z(]", 3, "="),
        (r"(?im)\b(?:ISOCALL|STOPRE|SETAL|DIAMON|DIAMOF|ATRANS|MCALL|REPEAT|WHENEVER|SPOS|EXTCALL)\b", 3, "ISOCALL|STOPRE|SETAL|DIAMO|ATRANS|MCALL|REPEAT|WHENEVER|SPOS|EXTCALL"),
        (r"(?im)\$(?:P|A|AA|AC|MC|MN|MA|SC|TC)_\w", 3, "$"), (r"(?im)^\s*(?:N\d+\s*)?[A-Z_]\w+:\s*(?:;|$)", 2, ":"),
        (r"(?im)^\s*(?:N\d+\s*)?_[A-Z]\w*\s*\(", 3, "_"), (r"(?im)\bIF\s+[A-Z(]", 2, "IF"),
        # structured control flow on its own line (ISO macros write WHILE [..] DOn / ENDn, Fagor $IF / $ENDIF)
        (r"(?im)^\s*(?:N\d+\s*)?(?:ELSE|ENDIF|ENDWHILE|ENDFOR|ENDLOOP|LOOP|REPEAT|UNTIL)\b", 5, "ELSE|END|LOOP|REPEAT|UNTIL"),
    ],
    "fagor": [
        (r"(?im)#(?:MCALL|PCALL|CALL|MDOFF|LATHECY|MILLCY|TOOL\s+AX)\b", 6, "#"), (r"(?im)\$(?:IF|GOTO|WHILE|FOR|SWITCH|ELSE|ENDIF|RPT|DO)\b", 5, "$"),
        (r"(?im)\bG16[0-5]\b", 4, "G16"), (r"(?im)\bG21[0-2]\b", 3, "G210|G211|G212"), (r"(?im)\(RPT\s+N", 5, "(RPT"), (r"(?im)\bV\.[A-Z]\.", 4, "V."),
        # Fagor cycle blocks: the tool-axis word is the reference plane and I the depth, no R (G81 Z2 I-20)
        # (ISO G81/G82/G84/G85 never take I; Haas G83 and ISO G87 may, always with an R point)
        (r"(?im)\bG8[1245]\b[^\n;(]*\bI[-+]?[\d.]", 15, "G81|G82|G84|G85"), (r"(?im)\bG8[1-8]\b(?![^\n;(]*\bR[-+]?[\d.])[^\n;(]*\bI[-+]?[\d.]", 15, "G8"),
        (r"(?im)^[ \t]*%L[ \t]+\w", 5, "%L"), (r"(?im)(?<![A-Z#\w])P\d+[ \t]*=(?!=)", 3, "="), (r"(?im)\bNR\d", 3, "NR"),
        (r"(?im)\bT\d+[ \t]*D\d+[ \t]*M0?6\b", 4, "D"), (r"(?im)\$(?:ENDIF|ENDWHILE|ENDFOR|ENDSWITCH|ENDDO|ELSEIF|CASE|BREAK)\b", 5, "$"),
        (r"(?im)^[ \t]*(?:N\d+[ \t]*)?#(?:HSC|MSG|ROUNDPAR|SET|SELECT|WAIT|RET|ERROR|TIME|CAX|RTCP|TLC|CS|ACS|COMMENT)\b", 12, "#"),
    ],
    "linuxcnc": [
        # O-word control flow, named parameters and active comments exist only in RS274NGC
        (r"(?im)^[ \t]*(?:N\d+[ \t]*)?O[ \t]*(?:\d+|<[^>\n]+>)[ \t]*(?:SUB|ENDSUB|CALL|IF|ELSEIF|ELSE|ENDIF|WHILE|ENDWHILE|DO|REPEAT|ENDREPEAT|RETURN|BREAK|CONTINUE)\b", 12, "SUB|CALL|IF|ELSE|WHILE|DO|REPEAT|RETURN|BREAK|CONTINUE"),
        (r"(?i)#<[^>\n]+>", 8, "#<"), (r"(?i)\((?:print|debug|msg|abort|log|logopen|logappend|logclose)\s*,", 8, "(PRINT|(DEBUG|(MSG|(ABORT|(LOG"),
        (r"(?im)^[ \t]*(?:N\d+[ \t]*)?[GMTXYZ][^;\n(]*;", 2, ";"), (r"(?i)\bG(?:64[ \t]*P|33\.1|38\.[2-5]|43\.1|92\.[123]|59\.[123]|7[ \t]|8[ \t]|41\.1|42\.1)", 4, "G64|G33.1|G38.|G43.1|G92.|G59.|G7 |G7\t|G8 |G8\t|G41.1|G42.1"),
        (r"(?im)\bG10[ \t]*L(?:1|10|11|20)\b", 4, "G10"), (r"(?im)\bM6[2-8][ \t]*P", 4, "M62|M63|M64|M65|M66|M67|M68"),
    ],
    "iso": [
        (r"(?m)^\s*%\s*$", 2, "%"), (r"(?im)^\s*(?:N\d+\s*)?O\d+", 4, "O"), (r"(?im)\bG0?[0-3](?![0-9.])\s*[XYZUW]", 2, "G"),
        (r"(?im)\bM(?:30|0?2|0?6)(?![0-9])", 2, "M30|M2|M02|M6|M06"), (r"(?im)\bG(?:4[0-4]|49|5[4-9]|8[0-9]|9[0-9]|7[0-6])(?![0-9])", 2, "G4|G5|G7|G8|G9"),
        (r"(?im)#\d+\s*=", 3, "#"), (r"(?im)\bIF\s*\[", 3, "["), (r"(?im)\bWH(?:ILE)?\s*\[", 3, "["), (r"(?im)\bM98\s*P", 3, "M98"),
        (r"(?im)\bG65\s*P", 3, "G65"), (r"(?im)^\s*N\d+\s*G\d", 2, "N"), (r"(?im)\bT\d+\s*M0?6\b", 2, "M6|M06"), (r"(?im)\bG\d+\s*X-?\d*\.\d*\s*Y", 1, "G"), (r"(?im)(?<![A-Z])[GM]\d+", 1, "G|M"),
    ],
}

_NOT_A_PROGRAM = [
    (r"(?m)^\s*#\s*(?:include|define|ifndef|ifdef|endif|pragma)\b", "C or C++ source", "#"),
    # a Python definition ends with a colon: SINUMERIK's own DEF and PROC lines, in lower case too, do not
    (r"(?m)^\s*(?:def|class)\s+\w+\s*(?:\(.*\))?\s*(?:->.*)?:\s*(?:#.*)?$|^\s*import\s+[\w.]+(?:\s+as\s+\w+)?\s*$|^\s*from\s+[\w.]+\s+import\s", "Python source", "DEF|CLASS|IMPORT"),
    (r"(?m)^\s*(?:public|private|static)?\s*(?:int|void|char|struct|typedef)\s+\w+", "C or C++ source", "INT|VOID|CHAR|STRUCT|TYPEDEF"),
    (r"(?s)^\s*[{\[]\s*\"", "JSON data", '"'),
    (r"(?s)^\s*<\?xml|^\s*<html", "XML or HTML", "<"),
]

# Languages of the ISO family's look that no reader here claims: (name, signals); a file
# showing two or more distinct signals of one of them is reported as that language, once,
# instead of being read as ISO and failing on every statement the ISO reader refuses.
_LOOKALIKES: list[tuple[str, list[tuple[str, str, str]]]] = [
    ("Fadal format", [
        (r"(?im)^\s*(?:N\d+\s*)?L\d{3,4}\s*$", "an L subroutine label line (L100)", "L"),
        (r"(?im)^\s*(?:N\d+\s*)?L\d{2,3}0[1-9]\s*$", "an L subroutine call with a repeat suffix (L101)", "L"),
        (r"(?im)\bG0?0\b[^\n(;]*\bE\d{1,2}\b", "an E fixture-offset word on a rapid (E1)", "E"),
        (r"(?im)^\s*(?:N\d+\s*)?H\d+\s+Z", "a length offset H without G43 (H6 Z10.)", "H"),
        (r"(?im)^\s*(?:N\d+\s*)?G8\s*$", "a G8 block", "G8"),
    ]),
    ("MillMaster Pro", [
        (r"(?m)^\s*//", "'//' comment lines", "//"),
        (r"(?im)^\s*G70\s*$", "G70 alone on a line (inch on MillMaster, a finishing cycle in ISO)", "G70"),
        (r"(?im)\bMillmaster\b", "the name MillMaster in a comment", "MILLMASTER"),
    ]),
    ("Okuma OSP", [
        (r"(?im)\bV[CS]\d+\s*=", "common variables VC1=", "="),
        (r"(?im)\bCALL\s+O\w+", "CALL O.. subprogram calls", "CALL"),
        (r"(?im)^\s*(?:N\d+\s*)?IF\s*\[[^\]]*\]\s*N\w+", "IF [..] N.. jumps", "IF"),
        (r"(?im)\bRTS\b", "RTS subprogram ends", "RTS"),
    ]),
]


class _Head:
    """The text that detection reads, with an upper-case copy when it is ASCII. A pattern
    none of whose needles occurs in that copy cannot match, so it is not run: upper-casing
    ASCII keeps every character in its place, and text that a pattern's literal matches
    (with or without IGNORECASE) reads as that literal in upper case. Text outside ASCII
    (whose case rules are wider) runs every pattern as written. On the upper-case copy a
    pattern that ignores case runs in its upper-case form (:func:`_upper_form`), which
    finds the same matches at the same places several times faster."""

    __slots__ = ("text", "upper", "_present", "_pairs")

    def __init__(self, text: str, skip_by_needles: bool = True):
        self.text = text
        self.upper = text.upper() if skip_by_needles and text.isascii() else None
        self._present: dict[str, bool] = {}  # needle -> found in the copy (patterns share needles)
        self._pairs = None  # which two-character sequences the copy holds, by their codes (read when first asked)

    def may_match(self, needles: str) -> bool:
        return self.upper is None or any(map(self._holds, needles.split("|")))

    def _holds(self, needle: str) -> bool:
        found = self._present.get(needle)
        if found is None:
            found = self._present[needle] = self._holds_pairs(needle) and needle in self.upper
        return found

    def _holds_pairs(self, needle: str) -> bool:
        """Does the copy hold every pair of adjacent characters of ``needle``? (A text
        without one of them cannot hold the needle; looking the pairs up is much cheaper than
        searching the whole text, which a needle of another dialect sends to its end.)"""
        if len(needle) < 2:
            return True
        if self._pairs is None:
            codes = numpy.frombuffer(self.upper.encode("ascii"), dtype=numpy.uint8).astype(numpy.int32)
            self._pairs = numpy.zeros(1 << 14, dtype=bool)
            self._pairs[codes[:-1] << 7 | codes[1:]] = True
        return all(self._pairs[ord(first) << 7 | ord(second)] for first, second in zip(needle, needle[1:]))

    def count(self, pattern: str, needles: str) -> int:
        """How often ``pattern`` matches, counted up to 3 (more weighs no more)."""
        if not self.may_match(needles):
            return 0
        return sum(1 for _ in itertools.islice(self._finditer(pattern), 3))

    def search(self, pattern: str, needles: str) -> bool:
        return self.may_match(needles) and next(self._finditer(pattern), None) is not None

    def _finditer(self, pattern: str):
        if self.upper is not None and _IGNORES_CASE.match(pattern):
            return _upper_form(pattern).finditer(self.upper)
        return re.finditer(pattern, self.text)


_IGNORES_CASE = re.compile(r"\(\?[a-zA-Z]*i[a-zA-Z]*\)")
# an opening word boundary before a letter or a class of letters, or a look-behind without
# groups or alternatives; then what it is moved behind: a letter and the letters and digits
# after it, or a class, none of it repeated
_LEADING_BOUNDARY = re.compile(r"(?:(\\b)(?=[A-Z]|\[[A-Z]+\])|\(\?<!((?:[^()|\\]|\\.)+)\))([A-Z][A-Z0-9]*|\[(?:[^\]\\]|\\.)+\])(?![?*+{])")


@functools.cache
def _upper_form(pattern: str) -> re.Pattern:
    """The case-ignoring ``pattern`` as it runs on upper-cased ASCII text: without
    IGNORECASE, each letter outside an escape in upper case, and a leading word boundary
    or look-behind moved behind the literal text or class that follows it (``\\bM6[2-8]``
    -> ``M6(?<!\\wM6)[2-8]``, ``(?<![A-Z])[GM]\\d`` -> ``[GM](?<![A-Z][GM])\\d``). On
    upper-case text the matches are the same; what changes is that a pattern opening with
    literal text lets the regex engine jump from one occurrence of that text to the next,
    where a case-ignoring one, or one opening with an assertion, tries a match at every
    character."""
    flags = _IGNORES_CASE.match(pattern)
    body = re.sub(r"\\.|[a-z]", lambda piece: piece.group(0) if piece.group(0).startswith("\\") else piece.group(0).upper(), pattern[flags.end():])
    opening = _LEADING_BOUNDARY.match(body)
    if opening is not None:
        boundary, behind, first = opening.groups()
        behind = r"\w" if boundary else behind
        body = f"{first}(?<!{behind}{first}){body[opening.end():]}"
    return re.compile(f"(?{flags.group(0)[2:-1].replace('i', '')}){body}" if flags.group(0) != "(?i)" else body)


def lookalike(head: str) -> tuple[str, list[str]] | None:
    """The unclaimed language the text looks like, with the signals seen, or None."""
    return _lookalike(_Head(head))


def _lookalike(head: _Head) -> tuple[str, list[str]] | None:
    for name, signals in _LOOKALIKES:
        seen = [what for pattern, what, needles in signals if head.search(pattern, needles)]
        if len(seen) >= 2:
            return name, seen
    return None


# Code words are found whether or not blocks put spaces between words (N10G50S2000): a word
# starts after anything but a letter and its number ends before anything but a digit.
_W = r"(?<![A-Z])"
_END = r"(?![0-9])"
_HAAS = (rf"(?im){_W}(?:G187|G103|G47|M97|G154){_END}|\bHAAS\b", "G187|G103|G47|M97|G154|HAAS")
_FANUC_LATHE = (rf"(?im){_W}G50\s*S\d|{_W}G9[024]\s*[XUZW]", "G50|G90|G92|G94")
_MITSUBISHI = (rf"(?im)(?:,[IJR]\s*-?\d|{_W}G1[23]\s*I[-.\d]+\s*D\d|{_W}G7[789]{_END})", ",|G12|G13|G77|G78|G79")
_LATHE = [
    (rf"(?im){_W}T\d{{4}}{_END}", 3, "T"), (rf"(?im){_W}G7[0-6]\s*P\d+\s*Q\d+", 4, "Q"), (rf"(?im){_W}G96{_END}", 2, "G96"),
    (rf"(?im){_W}G50\s*S", 2, "G50"), (rf"(?im){_W}G76\s*P\d{{6}}", 3, "G76"), (rf"(?im){_W}[UW]-?\d*\.\d*", 1, "U|W"),
    (rf"(?im){_W}G9[89]{_END}.*{_W}X", 1, "G98|G99"), (rf"(?im){_W}G18{_END}", 1, "G18"), (rf"(?im){_W}G7[0-3]\s*U", 3, "G70|G71|G72|G73"),
]
_MILL = [
    (rf"(?im){_W}Y-?\d*\.?\d", 2, "Y"), (rf"(?im){_W}G4[34]\s*[HZ]", 3, "G43|G44"), (rf"(?im){_W}G8[1-9]{_END}", 1, "G8"),
    (rf"(?im){_W}G17{_END}", 1, "G17"), (rf"(?im){_W}G5[4-9]{_END}", 1, "G5"), (rf"(?im){_W}M0?6{_END}", 2, "M6|M06"),
]


@dataclass(frozen=True)
class Detection:
    """The dialect a text is read as, how sure that is, and why."""

    dialect: str | None  # None: not a CNC program
    confidence: float
    reason: str = ""
    profile: str | None = None
    machine: str | None = None
    whole_units: bool = False  # integer coordinates are meant as whole mm/inch
    evidence: str = ""  # why: the scores, the extension, the profile's and machine type's signals (--verbose)


# The file extension is one signal among the content's: it tips a close call (a Fagor program
# without '#'/'$' statements in a .pim file) but never outweighs clear statements.
# A control's own extension weighs more than the generic ones many posts write.
_EXTENSIONS = {".h": ("heidenhain", 15), ".mpf": ("sinumerik", 15), ".spf": ("sinumerik", 15), ".pim": ("fagor", 15),
               ".pit": ("fagor", 15), ".nc": ("iso", 6), ".cnc": ("iso", 6), ".tap": ("iso", 6), ".min": ("iso", 6)}


def detect(head: str, raw_head: bytes = b"", suffix: str = "") -> Detection:
    return _detect(_Head(head), raw_head, suffix)


def _detect(found: _Head, raw_head: bytes, suffix: str) -> Detection:
    head = found.text
    raw = raw_head or head.encode("utf-8", "replace")
    if _looks_binary(raw):
        if _looks_utf16(raw):
            return Detection(None, 1.0, "UTF-16 text without a byte-order mark: save the program as UTF-8 (or UTF-16 with its byte-order mark)")
        return Detection(None, 1.0, "binary data, not a CNC program")
    for pattern, what, needles in _NOT_A_PROGRAM:
        if found.search(pattern, needles) and not found.search(r"(?im)^\s*(?:N\d+\s*)?G\d", "G"):
            return Detection(None, 0.9, f"looks like {what}, not a CNC program")
    scores = {dialect: _score(signatures, found) for dialect, signatures in _SIGNATURES.items()}
    if max(scores.values()) == 0:
        return Detection(None, 0.5, "no G-code, Klartext or SINUMERIK/Fagor statements found")
    by_extension, extension_weight = _EXTENSIONS.get(suffix.lower(), (None, 0))
    if by_extension is not None:
        scores[by_extension] += extension_weight
    best = max(scores, key=scores.get)
    total = sum(scores.values())
    confidence = scores[best] / total * min(1.0, scores[best] / 10.0)
    evidence = "signature scores " + ", ".join(f"{name} {score:g}" for name, score in sorted(scores.items(), key=lambda item: -item[1]) if score)
    if by_extension is not None:
        evidence += f" (the extension {suffix} counted {extension_weight} for {by_extension})"
    if best != "iso":
        return Detection(best, round(confidence, 2), evidence=evidence)
    other = _lookalike(found)
    if other is not None:
        name, seen = other
        return Detection("unclaimed", round(confidence, 2), f"looks like {name} ({', '.join(seen)}), not a language ncverify reads",
                         evidence=evidence)
    lathe, mill = _score(_LATHE, found), _score(_MILL, found)
    machine = _machine_of(lathe, mill)
    profile = _iso_profile(found, machine)
    evidence += f"; machine {machine or 'not told'} (lathe score {lathe}, mill score {mill})"
    evidence += f"; profile {profile}" + ("" if _profile_shown(found, machine) else " (assumed: no Haas, E60 or Fanuc-lathe codes seen)")
    return Detection("iso", round(confidence, 2), profile=profile, machine=machine,
                     whole_units=integers_look_whole(head), evidence=evidence)


def profile_evidence(head: str, machine: str | None = None) -> bool:
    """Does the text show which ISO control it is for, or is the E60 profile only assumed?"""
    return _profile_shown(_Head(head), machine)


def _profile_shown(head: _Head, machine: str | None) -> bool:
    return head.search(*_HAAS) or head.search(*_MITSUBISHI) or (machine == "lathe" and head.search(*_FANUC_LATHE))


def detect_iso_profile(head: str, machine: str | None = None) -> str:
    """Haas by its own codes; a lathe program clamping the spindle with G50 S uses the
    Fanuc list-A codes (Mitsubishi clamps with G92 S); otherwise the E60 reference."""
    return _iso_profile(_Head(head), machine)


def _iso_profile(head: _Head, machine: str | None) -> str:
    if head.search(*_HAAS):
        return "haas"
    if head.search(*_MITSUBISHI):
        return "mitsubishi-e60"
    if machine == "lathe" and head.search(*_FANUC_LATHE):
        return "fanuc"
    return "mitsubishi-e60"


# an axis or centre word not preceded by a letter, # or [ (the look-behind follows the letter,
# so that the search jumps from one such letter to the next)
_INTEGER_LENGTH = re.compile(r"[XYZUWIJKR](?<![A-Z#\[][XYZUWIJKR])[ \t]*-?(\d+)(?![\d.])")
_POINT_LENGTH = re.compile(r"[XYZUWIJKR](?<![A-Z#\[][XYZUWIJKR])[ \t]*-?\d*\.\d*")


def integers_look_whole(head: str) -> bool:
    """Do integer coordinates mean whole units? Controls with a least input increment read
    ``X8`` as 0.008 mm. A program where small integers are a good share of the coordinates
    (``X-1.4 Z8``, ``X 100 ... J -9.68``, or no decimal points at all) was written for
    whole units; programs in increments write large integers (``X-270000``), and a lone
    ``Z5`` among decimal values is a forgotten point (rule ``core.decimal-point``)."""
    code = re.sub(r"\([^)]*\)", "", head.upper())
    integers = [len(match.group(1)) for match in _INTEGER_LENGTH.finditer(code)]
    if not integers:
        return False
    points = sum(1 for _ in _POINT_LENGTH.finditer(code))
    mostly_small = sum(1 for digits in integers if digits <= 3) >= 0.8 * len(integers)
    return mostly_small and (points == 0 or len(integers) >= 0.25 * (len(integers) + points))


def _score(patterns, head: _Head) -> float:
    return sum(weight * head.count(pattern, needles) for pattern, weight, needles in patterns)


def detect_machine(head: str) -> str | None:
    found = _Head(head)
    return _machine_of(_score(_LATHE, found), _score(_MILL, found))


def _machine_of(lathe: float, mill: float) -> str | None:
    if lathe >= 4 and lathe > mill:
        return "lathe"
    if mill > 0:
        return "mill"
    return None


def _looks_utf16(raw: bytes) -> bool:
    """Text in UTF-16 (either byte order): one of each pair of bytes is almost always NUL,
    the other almost never."""
    sample = raw[:8192]
    if len(sample) < 4:
        return False
    halves = (sample[0::2], sample[1::2])
    nul_share = [half.count(0) / len(half) for half in halves]
    return max(nul_share) > 0.9 and min(nul_share) < 0.1


def _looks_binary(raw: bytes) -> bool:
    sample = raw[:8192]
    if not sample:
        return False
    if b"\x00" in sample:
        return True
    control = len(sample.translate(None, _NOT_CONTROL))  # the bytes left when every other is deleted
    return control / len(sample) > 0.05


_NOT_CONTROL = bytes(byte for byte in range(256) if byte >= 32 or byte in (9, 10, 12, 13, 26))
