"""Toleranced dimensions of the OCM standard shapes (reference B 6.21, seed L12155-12190).

A side length or diameter of 1271, 1272, 1273 or 1278 may be written as a text with a
tolerance; the control machines to the middle of the tolerance band and aborts with an
error on a text it cannot read. Three forms are accepted (case matters: H is a hole, h a
shaft):

    explicit deviations    10+0.01-0.015   middle of the band: 9.9975
    ISO 286-2 fit          10H7            middle of the band from the ISO tables
    ISO 2768-1 general     10m             symmetric: the nominal size

The ISO 286 tables are not carried here: a fit gives a value known only to lie within the
band's widest possible reach (``values.fresh``), so checks depending on it answer unknown.
"""
from __future__ import annotations

import re

from ... import values

_NUMBER = r"\d+(?:\.\d*)?|\.\d+"
_DEVIATIONS = re.compile(rf"({_NUMBER})([+-](?:{_NUMBER}))([+-](?:{_NUMBER}))")
_FIT_LETTERS = "A|B|C|CD|D|E|EF|F|FG|G|H|J|JS|K|M|N|P|R|S|T|U|V|X|Y|Z|ZA|ZB|ZC"
_FIT = re.compile(rf"({_NUMBER})(?:{_FIT_LETTERS}|{_FIT_LETTERS.lower()})(01|0|1[0-8]|[1-9])")
_GENERAL = re.compile(rf"({_NUMBER})[fmcv]")
_FIT_REACH = 0.05  # a fit's band lies within 5 % of the size (ISO 286 grades up to 18, sizes to 3150 mm)


def toleranced(text: str):
    """The size the control machines for a toleranced dimension, or None when the text is
    none of the three forms."""
    text = text.strip()
    found = _DEVIATIONS.fullmatch(text)
    if found:
        nominal, first, second = (float(part) for part in found.groups())
        return nominal + (first + second) / 2.0
    found = _GENERAL.fullmatch(text)
    if found:
        return float(found.group(1))
    found = _FIT.fullmatch(text)
    if found:
        nominal = float(found.group(1))
        return values.fresh(f"size {text}", nominal * (1.0 - _FIT_REACH), nominal * (1.0 + _FIT_REACH))
    return None
