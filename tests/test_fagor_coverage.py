"""Which rule checks each hazard (H1-H33) and each control alarm of the Fagor reference
(../shared/reference/fagor-8060-8065.md, section 11 and the cycle tables), or why it
cannot be decided from the program text and its context.

Each entry is (rule ids, note). The note says what the rules leave out; an entry with no
rule must give the reason in its note.
"""
from __future__ import annotations

import pytest

from ncverify.check import rule_definitions

EDITOR = ("out of scope: the conversational editor's cycles (G281-G299) are not saved as program text the cycles manual describes "
          "(reference §8.1, §12); G281-G299 in a program read as unknown codes (core.unknown-code)")

HAZARDS: dict[str, tuple[tuple[str, ...], str]] = {
    "H1": (("core.cycle-modal-at-end", "core.cycle-modal-at-tool-change"),
           "every later motion block is modelled as a hole (NR, NR0 too), so rapids and depths of the unwanted holes are judged; "
           "which move was 'the last intended hole' is the programmer's intent"),
    "H2": (("fagor.hole-at-unknown-position", "core.repeat-same-hole"),
           "NR in a cycle's zone repeats the hole in the cycle runner, so NRn in G90 (or G91 without an increment) is reported; "
           "a definition block at the position of an earlier hole of another block is not (it may be a second operation on purpose)"),
    "H3": (("core.cycle-depth-sign", "core.cycle-zero-depth", "fagor.g83-peck-count"), "judged with the tool-axis sign of #TOOL AX"),
    "H4": (("fagor.g83-depth", "core.cycle-missing-parameter"), "the intended depth is not known: judged against the stock's far face"),
    "H5": (("core.rapid-into-stock", "core.clearance-below-stock"),
           "both along any tool axis and sign; clearance-below-stock along X or Y only on a box stock"),
    "H6": (("core.rapid-into-stock",), "the approach to the surface + 1 mm (G87/G88) or the surface (G82, G210-G212) is a rapid segment"),
    "H7": (("core.cycle-r-above-initial", "core.rapid-into-stock"),
           "traverses between holes are judged against the stock; clamps and fixtures are not in the model"),
    "H8": (("fagor.unknown-start-plane",), ""),
    "H9": (("fagor.g82-retract-coordinate",), "judged at the first peck; later pecks are deeper"),
    "H10": (("fagor.g82-parameters",), ""),
    "H11": (("fagor.cycle-starts-spindle", "core.tapping-spindle-direction"), "whether a tap is left-hand is not in the tool table"),
    "H12": (("fagor.pocket-incremental-depth",), ""),
    "H13": (("fagor.pocket-tool-fit", "fagor.pocket-parameters", "fagor.pocket-finishing-only", "core.feed-missing"), ""),
    "H14": (("fagor.pocket-tool-fit", "fagor.pocket-parameters", "fagor.pocket-finishing-only"), ""),
    "H15": (("core.duplicate-address",), "letter shadowing itself is done by the lowering (tests/test_fagor.py: M1 and D2 of G87 are parameters)"),
    "H16": ((), "not a finding: the lowering files the tool-axis word of a cycle block as the reference plane "
                "(tests/test_fagor.py: test_tool_axis_word_in_the_cycle_block_is_the_reference_plane_in_g19)"),
    "H17": (("core.cycle-depth-sign", "core.cycle-r-above-initial"),
            "the sign of #TOOL AX [..+/-] is carried by every hole; a tool axis in the plane or a secondary axis (X2) is not modelled"),
    "H18": (("fagor.g86-back-off",), "A0/A1 with Q and a back-off answers unknown once per definition ('verify the direction': it depends "
                                    "on the machine's spindle orientation reference and the bar's clamping), Q with no D/E is reported; the "
                                    "bar-to-bore clearance against hypot(D, E) needs the bar's size, which the tool table does not give; "
                                    "R0 scratching a finish bore is the programmer's choice of retract"),
    "H19": (("fagor.rigid-tapping-encoder", "core.tap-feed-pitch"), "the locked override and the spindle stop under K are what the cycle does, not hazards"),
    "H20": (("fagor.pocket-tool-fit", "fagor.bore-milling-parameters", "fagor.bore-milling-no-floor", "core.cycle-missing-parameter"), ""),
    "H21": (("fagor.thread-mill-overshoot",), "the overshoot is taken as one pitch (the manual gives no length); a blind hole's own bottom is not known"),
    "H22": (("fagor.thread-mill-parameters", "fagor.pocket-tool-fit", "core.rapid-into-stock"),
            "G212's rapids run at the entry radius |J|/2 + R + E at the start angle Q and are judged against the blank (without E: down "
            "over the stud's centre, then out); the helix is drawn as a feed along the tool axis at the entry point, one radial pass of "
            "several; without the tool radius in the tool table they answer unknown. A rapid down beside the stud (B negative) or down "
            "the pre-drilled hole (G211) answers unknown: the stock model holds no cleared material or holes"),
    "H23": (("fagor.pattern-without-cycle", "fagor.pattern-parameters", "fagor.pattern-skip-list"), ""),
    "H24": (("fagor.pattern-moves", "core.rapid-into-stock"), "bosses inside a G163-G165 circle are not in the stock model"),
    "H25": ((), "not a finding: the pattern runner keeps the cycle active and leaves the tool at the last machined point"),
    "H26": (("fagor.vc-absolute", "fagor.cycle-data-without-cycle"), ""),
    "H27": (("fagor.pattern-without-cycle", "fagor.cycle-data-without-cycle"),
            "the cancellation itself is modelled (G17-G19, G20, #TOOL AX, G74, M02/M30 end the zone)"),
    "H28": (("fagor.cycle-set-left-on", "fagor.turning-cycle"), ""),
    "H29": (("fagor.dwell-seconds",), ""),
    "H30": ((), EDITOR),
    "H31": ((), EDITOR),
    "H32": ((), EDITOR),
    "H33": (("fagor.arc-positioning-in-cycle",), ""),
}

# The alarms the cycles manual names (reference §6, §7, §8.4)
ALARMS: dict[str, tuple[tuple[str, ...], str]] = {
    "G82 C=0 (seed L941-946)": (("fagor.g82-parameters",), ""),
    "G87/G88 stepover C wider than the tool (seed L1386-1390, L1499-1503)": (("fagor.pocket-tool-fit",), ""),
    "G210 J missing or smaller than the tool (seed L1599-1604)": (("core.cycle-missing-parameter", "fagor.pocket-tool-fit"), ""),
    "G210 tool radius not below J/2 or below (J-K)/4 (seed L1609-1613)": (("fagor.pocket-tool-fit",), ""),
    "G160-G165 outside a cycle's zone (seed L1961-1964)": (("fagor.pattern-without-cycle",), ""),
    "G160-G162 length and step that do not give whole points (seed L2027, L2106, L2138)": (("fagor.pattern-parameters",), ""),
    "G163 step not dividing 360, G164 step not dividing B (seed L2247-2248, L2323-2324)": (("fagor.pattern-parameters",), ""),
    "skip letters P-V out of order (seed L1998-1999, L2032-2033)": (("fagor.pattern-skip-list",), ""),
    "V.C.x with no active cycle (derived, H26)": (("fagor.cycle-data-without-cycle",), ""),
    "editor: plunge step I=0 with the table's cutting length 0 (seed L2785-2809)": ((), EDITOR),
    "editor: N=0 with table length 0 and different roughing/finishing tools (seed L2805-2809)": ((), EDITOR),
    "editor bore milling tool conditions (seed L3101-3105)": ((), EDITOR),
}


def test_every_hazard_of_the_reference_is_mapped():
    assert sorted(HAZARDS, key=lambda name: int(name[1:])) == [f"H{number}" for number in range(1, 34)]


@pytest.mark.parametrize("name, entry", [*HAZARDS.items(), *ALARMS.items()])
def test_every_named_rule_exists_and_every_gap_says_why(name, entry):
    rules, note = entry
    definitions = rule_definitions()
    assert [rule for rule in rules if rule not in definitions] == []
    assert rules or note, f"{name}: no rule and no reason"
