"""No program made of a dialect's real statements, in any order and with any values, makes
the pipeline raise: the lowering, the interpreter, the frames, the cycle models and every
rule see each other's output in combinations nobody wrote a test for."""
from __future__ import annotations

from hypothesis import HealthCheck, given, settings, strategies as st

from ncverify import Settings, check_text

_NUMBER = st.sampled_from(["0", "1", "-1", "2.5", "-20", "45", "90", "100", "0.001", "-0.5", "360", "1000"])


def _filled(template: str):
    """A line template with ``{}`` holes filled by numbers that matter to the rules
    (zero, negative, large, fractional)."""
    return st.lists(_NUMBER, min_size=template.count("{}"), max_size=template.count("{}")).map(lambda values: template.format(*values))


def _program(templates: list[str], head: list[str], tail: list[str]):
    lines = st.lists(st.sampled_from(templates).flatmap(_filled), min_size=1, max_size=14)
    return lines.map(lambda body: "\n".join(head + body + tail) + "\n")


KLARTEXT = [
    "L X{} Y{} Z{} R0 FMAX", "L X{} Y{} R0 F{}", "L IX{} IY{} RL F200", "L Z{} R0 FMAX M3", "CC X{} Y{}", "C X{} Y{} DR+",
    "CR X{} Y{} R{} DR-", "CYCL DEF 7.0 DATUM SHIFT", "CYCL DEF 7.1 X{}", "CYCL DEF 7.2 IY{}", "CYCL DEF 8.0 MIRROR IMAGE",
    "CYCL DEF 8.1 X", "CYCL DEF 10.0 ROTATION", "CYCL DEF 10.1 ROT{}", "CYCL DEF 11.0 SCALING", "CYCL DEF 11.1 SCL{}",
    "CYCL DEF 26.0 AXIS-SPEC. SCALING", "CYCL DEF 26.1 X{} Y{} CCX{} CCY{}", "CYCL DEF 19.0 WORKING PLANE", "CYCL DEF 19.1 A{} B{} C{}",
    "TRANS DATUM AXIS X{} Y{}", "TRANS DATUM RESET", "PLANE RESET STAY",
    "CYCL DEF 200 DRILLING Q200={} Q201={} Q206={} Q202={} Q210=0 Q203={} Q204={} Q211=0 Q395={}",
    "CYCL DEF 240 CENTERING Q200={} Q343={} Q201={} Q344={} Q206=200 Q211=0 Q203={} Q204={} Q342={}",
    "CYCL DEF 251 RECTANGULAR POCKET Q215=0 Q218={} Q219={} Q220={} Q368=0 Q224=0 Q367=0 Q207=500 Q351=1 Q201={} Q202={} Q369=0 Q206=150 Q338=0 Q200=2 Q203={} Q204=50 Q370=1 Q366=0 Q385=500",
    "CYCL DEF 232 FACE MILLING Q389=0 Q225={} Q226={} Q227={} Q386={} Q218={} Q219={} Q202={} Q369=0 Q370=1 Q207=500 Q385=500 Q253=750 Q200=2 Q357=2 Q204=50",
    "CYCL DEF 225 ENGRAVING QS500=\"AB\" Q513={} Q514=0 Q515=0 Q516=0 Q367=0 Q574={} Q575=0 Q517={} Q207=750 Q201={} Q206=300 Q200=2 Q203={} Q204=50",
    "CYCL CALL", "CYCL CALL POS X{} Y{} Z{}", "M99", "M89", "M5", "M3", "TOOL CALL 1 Z S{}", "Q1 = Q2 / {}", "Q2 = {}",
    "FN 9: IF +Q1 EQU +{} GOTO LBL 1", "LBL 1", "CALL LBL 1 REP {}",
]
SINUMERIK = [
    "G0 X{} Y{} Z{}", "G1 X{} Y{} F{}", "G2 X{} Y{} CR={}", "G91 G1 X{}", "G90", "TRANS X{} Y{}", "ATRANS Z{}", "ROT RPL={}",
    "AROT RPL={}", "SCALE X{} Y{}", "MIRROR X0", "TRANS", "G58 X{}", "CYCLE800(1,\"\",0,57,0,0,0,{},0,0,0,0,0,1)",
    "MCALL CYCLE81({},{},{},{})", "MCALL", "HOLES1({},{},{},{},{},{})", "CYCLE83({},{},{},{},{},{},{},{},{},{},{},{})",
    "POCKET3({},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{})", "SLOT2({},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{})",
    "CYCLE71({},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{})", "CYCLE90({},{},{},{},{},{},{},{},{},{},{},{},{})",
    "CYCLE95(\"C1\",{},{},{},{},{},{},{},{},{},{},{},{})", "CYCLE93({},{},{},{},{},{},{},{},{},{},{},{},{},{},{})",
    "T{} D{}", "M6", "S{} M3", "M5", "$TC_DP24[1,1]={}", "$TC_DP2[1,1]={}", "R1=R2/{}", "DIAMON", "DIAMOF",
]
FAGOR = [
    "G0 X{} Y{} Z{}", "G1 X{} Y{} F{}", "G2 X{} Y{} I{} J{}", "G91 G1 X{}", "G90", "G81 Z{} I{}", "G82 Z{} I{} B{} J{} C{} H{}",
    "G83 Z{} I{} J{}", "G87 Z{} I{} J{} K{} B{} C{} D{} L{}", "G88 Z{} I{} J{} B{} C{} D{}", "G210 Z{} I{} J{} K{} B{} D{}",
    "G212 Z{} I{} J{} K{} B{} E{}", "G160 A{} X{} I{} NR{}", "G163 X{} I{} C{}", "X{} Y{} NR{}", "G80", "G98", "G99",
    "#TOOL AX [Z-]", "#TOOL AX [X+]", "#TOOL AX [Z+]", "#MCALL [\"SUB\"]", "#MDOFF", "#LATHECY ON", "#LATHECY OFF", "G17", "G19",
    "T{} D{}", "M6", "S{} M3", "M5", "P1 = {}", "$IF P1 == {}", "$ENDIF", "G84 Z{} I{} R1",
]
_STOCK_KLARTEXT = ["0 BEGIN PGM F MM", "1 BLK FORM 0.1 Z X+0 Y+0 Z-20", "2 BLK FORM 0.2 X+100 Y+100 Z+0", "3 TOOL CALL 1 Z S2000",
                   "4 L Z+100 R0 FMAX M3"]
_STOCK_SINUMERIK = ["WORKPIECE(,\"\",,\"BOX\",0,0,-20,-80,0,0,100,100)", "T1 D1", "M6", "S2000 M3", "G0 X0 Y0 Z50"]
_STOCK_FAGOR = ["; ncverify: stock box X0:100 Y0:100 Z-20:0", "; ncverify: tool 1 radius 4", "T1 D1", "M6", "S2000 M3", "G0 X0 Y0 Z50"]

_FUZZ = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
_SETTINGS = dict(loop_bound=20, max_paths=4, solver_timeout_s=0.5)


@_FUZZ
@given(_program(KLARTEXT, _STOCK_KLARTEXT, ["L Z+100 R0 FMAX M30", "END PGM F MM"]))
def test_klartext_statements_in_any_order_never_raise(text):
    check_text(text, "f.h", Settings(dialect="heidenhain", **_SETTINGS))


@_FUZZ
@given(_program(SINUMERIK, _STOCK_SINUMERIK, ["M30"]))
def test_sinumerik_statements_in_any_order_never_raise(text):
    check_text(text, "f.mpf", Settings(dialect="sinumerik", **_SETTINGS))


@_FUZZ
@given(_program(FAGOR, _STOCK_FAGOR, ["M30"]))
def test_fagor_statements_in_any_order_never_raise(text):
    check_text(text, "f.pim", Settings(dialect="fagor", **_SETTINGS))
