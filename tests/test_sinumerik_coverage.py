"""What the SINUMERIK references ask a verifier to find, and where ncverify finds it.

Every hazard of reference A section 9 (items 1-43) and reference B section 9 (items 1-46),
and every alarm number of the alarm tables (reference B section 11, reference A Appendix A
with the numbers its ranges point to in A sections 6.24 and 6.25), maps either to the rule
ids that check it or to the reason it cannot be decided from a part program. A reason that
starts with "not checked yet" is a gap that could be closed; the others are facts about
what a program does not contain.
"""
from __future__ import annotations

from ncverify.check import rule_definitions

MACHINE_DATA = "depends on machine data or options the part program does not contain"
RUN_TIME = "raised by the control's own computation or file handling at run time"
MODELLED = "a modelling fact, not a defect: the interpreter follows it (tested in test_sinumerik*.py)"

HAZARDS_A = {
    1: ("sinumerik.reference-plane",),
    2: ("sinumerik.reference-plane",),
    3: ("core.cycle-depth-sign", "core.cycle-zero-depth", "sinumerik.reference-plane", "sinumerik.milling-depth-sign"),
    4: ("sinumerik.cycle-parameter-range",),
    5: ("sinumerik.depth-conflict",),
    6: ("sinumerik.retract-inside-clearance",),
    7: ("core.rapid-into-stock", "sinumerik.start-below-surface"),
    8: MODELLED + " (the infeed axis is the applicate of G17/G18/G19); 61005 needs the machine's axes",
    9: "_ZSD[1] is a setting of the machine's cycle data (GUD7), not written in part programs",
    10: "which dimensioning the programmer meant is not in the program (POCKET3 plunges where the _ZSD[2] it sets puts the centre)",
    11: ("core.cycle-modal-at-tool-change", "core.cycle-modal-at-end"),  # a modal cycle or a modal subprogram call
    12: ("sinumerik.pattern-without-mcall",),
    13: ("sinumerik.nested-mcall",),
    14: ("sinumerik.hole-count",),
    15: ("sinumerik.contour-section-runs",),
    16: ("core.label-not-found", "core.duplicate-label"),
    17: ("sinumerik.cycle-not-alone",),
    18: ("sinumerik.cycle-arguments",),
    19: ("sinumerik.shifted-arguments",),
    20: ("sinumerik.hole-count", "sinumerik.cycle-parameter-range", "sinumerik.turning-parameters"),
    21: ("sinumerik.no-tool-offset", "sinumerik.cutter-radius"),
    22: ("sinumerik.cutter-radius",),
    23: ("sinumerik.cutter-radius",),
    24: ("sinumerik.cycle-parameter-range", "sinumerik.cutter-radius"),
    25: ("sinumerik.cutter-radius", "sinumerik.pocket-contour"),
    26: ("sinumerik.cycle-parameter-range", "sinumerik.cutter-radius"),
    27: ("sinumerik.cycle-parameter-range",),
    28: ("sinumerik.hole-count",),
    29: ("sinumerik.spindle-at-cycle",),
    30: ("sinumerik.milling-direction",),
    31: ("sinumerik.thread-pitch",),
    32: ("sinumerik.spindle-direction",),
    33: ("core.spindle-off-cutting",),
    34: MACHINE_DATA + " (a position-controlled spindle, the override switch)",
    35: ("sinumerik.first-depth", "sinumerik.cycle-parameter-range"),
    36: ("sinumerik.thread-mill-bore",),  # a bore drilled in the program; external threads' free space is not judged
    37: ("sinumerik.cycle-parameter-range",),
    38: ("sinumerik.cycle-parameter-range", "sinumerik.path-milling-contour", "sinumerik.contour-section-runs"),
    39: ("sinumerik.pocket-contour", "sinumerik.pocket-edge"),
    40: ("sinumerik.engraving-text", "sinumerik.cycle-parameter-range"),
    41: ("sinumerik.swivel-plane",),
    42: ("sinumerik.high-speed-settings",),
    43: MODELLED,
}

HAZARDS_B = {
    1: ("sinumerik.no-tool-offset",),
    2: ("sinumerik.turning-parameters",),
    3: "the width of a grooving tool (two cutting edges) is not in the tool model",
    4: ("sinumerik.turning-parameters",),
    5: "the reference derives the base-corner test itself and leaves the direction of DIAG uncertain",
    6: ("sinumerik.undercut-form",),
    7: ("sinumerik.turning-parameters",),
    8: "the DIN 76-1 table of thread sizes is not in the references",
    9: ("sinumerik.turning-parameters",),
    10: ("sinumerik.machining-type",),
    11: ("sinumerik.stock-removal-contour",),
    12: ("sinumerik.stock-removal-contour",),
    13: ("sinumerik.stock-removal-contour",),
    14: ("sinumerik.stock-removal-contour",),
    15: "the size of the contour table depends on the contour and the control (no limit given)",
    16: ("sinumerik.stock-removal-contour",),
    17: ("sinumerik.clearance-angle",),
    18: ("sinumerik.thread-pitch",),
    19: ("sinumerik.turning-parameters",),
    20: ("sinumerik.cycle-arguments",),
    21: ("sinumerik.extended-stock-removal",),
    22: ("sinumerik.contour-direction",),
    23: MODELLED + " (no defect: the swept region grows)",
    24: ("sinumerik.contour-direction",),
    25: ("sinumerik.stock-removal-contour",),
    26: MODELLED,
    27: ("sinumerik.turning-parameters",),
    28: ("sinumerik.turning-parameters",),
    29: ("sinumerik.groove-dwell",),
    30: "a surface-quality trade-off the programmer chooses, not a defect",
    31: "the allowances are summed by design; no wrong value is defined",
    32: "a unit fact (1 inch under G70), not a defect",
    33: "the internally computed start point of the turning cycles is not modelled",
    34: ("sinumerik.spindle-at-cycle",),
    35: ("sinumerik.thread-infeed-angle",),  # IANG < 0 on a taper thread runs single-flank: a documented behaviour
    36: MODELLED + " (no defect)",
    37: ("sinumerik.turning-parameters",),
    38: ("sinumerik.clearance-angle",),  # under a rotation or scale frame: unknown; with P24 = 0 the real angle is not known
    39: "a message, not a defect: the cycle adapts the form",
    40: "_ZSD[6] and orientable toolholders are machine data",
    41: MACHINE_DATA + " (the master spindle)",
    42: ("sinumerik.undercut-feed",),
    43: MODELLED,
    44: ("sinumerik.extended-stock-removal",),  # RND/CHF at the end, contours coinciding; names and directories are outside one program
    45: MACHINE_DATA + " (option, HMI, NCK software)",
    46: "the recutting offset is a GUD value stored at run time",
}

ALARMS = {
    10930: "sinumerik.stock-removal-contour", 10931: "sinumerik.stock-removal-contour",
    10933: "sinumerik.stock-removal-contour", 10934: "the contour table's size is not documented",
    12330: "sinumerik.cycle-arguments", 12340: "sinumerik.cycle-arguments",
    15800: "sinumerik.stock-removal-contour", 15810: "its trigger is not given in the references",
    61000: "sinumerik.no-tool-offset", 61001: "sinumerik.thread-pitch", 61002: "sinumerik.machining-type",
    61003: "sinumerik.cycle-parameter-range",
    61005: MACHINE_DATA + " (whether a Y axis exists)",
    61009: "sinumerik.no-tool-offset", 61010: "sinumerik.cycle-parameter-range",
    61011: "sinumerik.scaled-cycle",
    61012: "sinumerik.scaled-cycle",
    61014: "its trigger is not stated beyond 'check RTP'",
    61019: "sinumerik.cycle-parameter-range",
    61101: "sinumerik.reference-plane", 61102: "sinumerik.spindle-direction", 61103: "sinumerik.hole-count",
    61104: "the slot arrangement rule is not given (only 'inconsistent')",
    61105: "sinumerik.cutter-radius", 61106: "sinumerik.hole-count", 61107: "sinumerik.first-depth",
    61108: "sinumerik.cycle-parameter-range",
    61109: "sinumerik.milling-direction", 61110: "sinumerik.cycle-parameter-range",
    61111: "sinumerik.cutter-radius", 61112: "sinumerik.cutter-radius", 61113: "sinumerik.cycle-parameter-range",
    61114: "sinumerik.cycle-parameter-range", 61115: "sinumerik.cycle-parameter-range",
    61116: "sinumerik.cycle-parameter-range", 61117: "sinumerik.cutter-radius", 61118: "sinumerik.cycle-parameter-range",
    61124: "raised only in simulation without a tool",
    61125: "sinumerik.technology-digits",
    61126: "depends on the spindle's acceleration at run time",
    61127: MACHINE_DATA + " (MD 31050/31060)",
    61128: "sinumerik.cycle-parameter-range",
    61176: "the character widths of the engraving font are not in the references",
    61178: "sinumerik.cycle-parameter-range", 61179: "sinumerik.engraving-text",
    61180: MACHINE_DATA + " ($MN_MM_NUM_TOOL_CARRIER)", 61181: MACHINE_DATA + " (NCK software version)",
    61182: MACHINE_DATA + " (the swivel data records set up at commissioning)",
    61183: "sinumerik.swivel-plane",
    61184: "sinumerik.swivel-plane",
    61185: MACHINE_DATA, 61186: MACHINE_DATA, 61187: "raised by block search, an operator action", 61188: MACHINE_DATA,
    61189: "sinumerik.swivel-plane", 61190: MACHINE_DATA + " (the retract limits)",
    61196: "raised in JOG, not by a part program", 61199: MACHINE_DATA,
    61191: MACHINE_DATA, 61192: MACHINE_DATA, 61193: MACHINE_DATA, 61194: MACHINE_DATA,
    61200: "the element limit is not stated", 61213: "the smallest circle radius is not stated",
    61215: "sinumerik.cycle-parameter-range",
    61601: "sinumerik.turning-parameters", 61602: "the grooving tool's width is not in the tool model",
    61603: "sinumerik.turning-parameters", 61604: "sinumerik.clearance-angle",
    61605: "its trigger is not stated beyond 'illegal undercut element'; overhangs (no alarm) are sinumerik.contour-direction",
    61606: "sinumerik.stock-removal-contour", 61607: "sinumerik.stock-removal-contour",
    61608: "sinumerik.edge-position",
    61609: "sinumerik.undercut-form", 61610: "its cycles are uncertain in the references",
    61611: RUN_TIME, 61612: RUN_TIME, 61613: "sinumerik.turning-parameters",
    61701: "sinumerik.extended-stock-removal",
    61702: "a run without a blank is a documented option; an open blank contour is 61740",
    **{number: RUN_TIME for number in (61703, 61704, 61705, 61706, 61707, 61708, 61709, 61720, 61721, 61722, 61723,
                                        61725, 61726, 61727, 61728, 61729, 61730, 61731, 61732, 61733, 61741, 61742)},
    61724: "sinumerik.extended-stock-removal",
    61734: "which cutting-edge positions suit which cutting direction is not stated in the references",
    61735: "sinumerik.extended-stock-removal",
    61736: "the tool's plunge length is not in the tool model", 61737: "the tool's cut depths are not in the tool model",
    61738: "the tool's cut depths are not in the tool model", 61739: RUN_TIME,
    61740: "sinumerik.extended-stock-removal",
    61803: MACHINE_DATA + " (which axes exist)",
    61807: "sinumerik.spindle-direction",
    61900: "sinumerik.pocket-contour", 61901: "sinumerik.pocket-contour",
    **{number: RUN_TIME for number in (61902, 61903, 61904, 61906, 61907, 61908, 61909, 61910, 61911, 61912, 61913,
                                        61914, 61915, 61916, 61917, 61918, 61980, 61981, 61983, 61985, 61986, 61987, 61988)},
    61905: "sinumerik.cutter-radius",  # SLOT2 with a tool below half the width; CYCLE73 computes it at run time
    61982: "sinumerik.pocket-contour", 61984: "sinumerik.pocket-contour",
    61989: "sinumerik.pocket-edge",
    62100: "sinumerik.pattern-without-mcall", 62101: "sinumerik.milling-direction",
    62105: "sinumerik.hole-count",
    62180: "a message asking the operator to set a manual rotary axis", 62181: "a message asking the operator to set a manual rotary axis",
    62185: "a message: the angle is adapted to the Hirth grid of the machine", 62186: "raised in JOG", 62187: "raised in JOG",
}


def _named_rules(entry) -> tuple[str, ...]:
    if isinstance(entry, tuple):
        return entry
    return (entry,) if entry.startswith(("sinumerik.", "core.")) else ()


def test_every_hazard_of_both_references_is_mapped():
    assert sorted(HAZARDS_A) == list(range(1, 44))
    assert sorted(HAZARDS_B) == list(range(1, 47))


def test_every_alarm_of_the_tables_is_mapped():
    tables = {10930, 10931, 10933, 10934, 12330, 12340, 15800, 15810, 61000, 61001, 61002, 61003, 61005, 61009, 61010,
              61011, 61012, 61014, 61019, *range(61101, 61119), 61124, 61125, 61126, 61127, 61128, 61176, 61178, 61179,
              *range(61180, 61195), 61196, 61199, 61200, 61213, 61215, *range(61601, 61614), *range(61701, 61710),
              *range(61720, 61743), 61803, 61807, *range(61900, 61919), *range(61980, 61990), 62100, 62101, 62105,
              62180, 62181, 62185, 62186, 62187}
    assert tables <= set(ALARMS), sorted(tables - set(ALARMS))


def test_every_named_rule_exists_and_every_reason_says_something():
    known = set(rule_definitions())
    for entry in (*HAZARDS_A.values(), *HAZARDS_B.values(), *ALARMS.values()):
        named = _named_rules(entry)
        assert set(named) <= known, set(named) - known
        assert named or len(entry) > 12


def test_the_page_of_a_rule_named_for_an_alarm_names_the_alarm():
    definitions = rule_definitions()
    for number, entry in ALARMS.items():
        for rule_id in _named_rules(entry):
            assert str(number) in definitions[rule_id].path.read_text(encoding="utf-8"), (number, rule_id)
