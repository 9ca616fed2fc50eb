"""Each control's statement forms, read without a syntax finding: control flow (including
the jumps that do not alarm when the target is missing), repeat counts in their written
forms, external declarations, string functions and comparisons, system variables and
constants, macro output statements, a blank before a function's parenthesis, a block
number written against the next word and axis variables in frames. One program per form;
the dialect is the one the file's extension and content name."""
from __future__ import annotations

import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_text
from ncverify.diagnostics import Status

DIALECTS = {"nc": "iso", "mpf": "sinumerik", "h": "heidenhain", "pim": "fagor"}
FORMS = {  # extension -> programs, each using one form
 "nc": [
  "IF [#1 EQ 0] GOTO 10\nN10 M30\n", "IF [#1 EQ 0] THEN #2 = 1\nM30\n", "WHILE [#1 LT 10] DO 1\n#1 = #1 + 1\nEND 1\nM30\n",
  "#5 = 10\nGOTO #5\nN10 M30\n", "M98 P1000 L3\nM30\nO1000\nM99\n", "M98 P31000\nM30\nO1000\nM99\n", "M98 P1000 K3\nM30\nO1000\nM99\n",
  "G65 P1000 L2 A1. B2.\nM30\nO1000\nM99\n", "#3000=1 (BAD INPUT)\nM30\n", "#1 = #5221\nG0 X#1\nM30\n", "#1=#4001\nM30\n",
  "#1 = 2\n#[#1] = 5\nG0 X#2\nM30\n", "POPEN\nDPRNT[X#101[43]*Y#102[43]]\nPCLOS\nM30\n", "BPRNT[X#101[43]]\nM30\n",
  "#1 = SIN [30.]\nG0 X#1\nM30\n", "#1=ABS [-2.]\nM30\n", "N10G0X0Y0\nN20G1X10.F100.\nM30\n", "N10 G0 X0\nM97 P100 L2\nM30\nN100 G0 X1\nM99\n",
  "#1 = ATAN[1.]/[1.]\nM30\n", "#1 = ROUND[2.5] + FUP[1.2] + FIX[1.7]\nM30\n", "#1 = [1 OR 2] AND 3 XOR 1\nM30\n",
  "#100 = #0\nIF [#100 EQ #0] GOTO 5\nN5 M30\n", "#3006 = 1 (LOOK)\nM30\n", "#1 = #3001\nM30\n", "G10 L2 P1 X0 Y0 Z0\nM30\n",
 ],
 "mpf": [
  "GOTOF L1\nL1:\nM30\n", "GOTOB L1\nM30\n", "GOTO L1\nL1: M30\n", "GOTOC MISSING\nM30\n", "IF R1>0 GOTOF L1\nL1: M30\n",
  "DEF INT I\nFOR I=1 TO 5\nENDFOR\nM30\n", "R1=0\nWHILE R1<3\nR1=R1+1\nENDWHILE\nM30\n", "R1=0\nREPEAT\nR1=R1+1\nUNTIL R1>3\nM30\n",
  "LOOP\nGOTOF END1\nENDLOOP\nEND1:\nM30\n", "CASE R1 OF 1 GOTOF A1 DEFAULT GOTOF A2\nA1:\nA2:\nM30\n",
  "L1:\nG0 X0\nL2:\nREPEAT L1 L2 P=3\nM30\n", "A1: G0 X1\nREPEATB A1 P=2\nM30\n", "L100 P3\nM30\n", "CALL \"L100\"\nM30\n",
  "EXTERN SUB1(REAL, INT)\nSUB1(1.5, 2)\nM30\n", "DEF STRING[20] S1=\"ABC\"\nIF S1==\"ABC\" GOTOF L1\nL1: M30\n",
  "DEF STRING[20] S1=\"ABC\"\nR1=STRLEN(S1)\nR2=INDEX(S1,\"B\")\nS1=SUBSTR(S1,0,1)<<\"X\"\nM30\n",
  "R1=$P_TOOLNO\nR2=$AA_IM[X]\nR3=$PI\nM30\n", "MSG(\"TEXT\" << R1)\nMSG()\nM30\n", "DEF INT ERR\nWRITE(ERR,\"LOG\",\"LINE\")\nM30\n",
  "N10G0X0Y0\nN20G1X10F100\nM30\n", "R1 = SIN (30)\nM30\n", "R1 = 5\nTRANS X=R1 Y=-R1\nTRANS\nM30\n",
  "$P_UIFR[1,X,TR]=10\nM30\n", "DEF AXIS AX1=X\nG0 AX[AX1]=10\nM30\n", "G0 AX[AXNAME(\"X\")]=10\nM30\n", "SETAL(61000)\nM30\n",
  "R1=TRUNC(2.5)+ROUND(1.5)+ABS(-1)\nM30\n", "IF (R1==1) AND (R2<>2) GOTOF L1\nL1: M30\n", "STOPRE\nM30\n",
  "proc LIMIT(int count, real size)\ndef int k\nk=count*2\nif (k>10) and (size<0)\nsetal(61001)\nendif\nret\n",
  "def real step\nstep=0.5\nwhile step<4\nstep=step*2\nendwhile\nm30\n",
  "OSP1[Z]=10 OSP2[Z]=40\nOSCTRL[Z]=(1+2,16+32)\nM30\n",
  "DEF INT SLOT[4], ORDER[4], K\nK=1\nORDER[K]=2\nR1=SLOT[ORDER[K]]+SLOT[ORDER[K]+1]\nM30\n",
  "R3 = ABS ( $AA_IM [ X ] ) + $P_UIFR [ 1 , Y , TR ]\nM30\n", "$P_UIFR[2]=CTRANS(X,-12.5,Y,40):CROT(Z,30)\nG55\nM30\n", "N10DEF INT K=2\nN20GOTOF DONE\nN30 K=3\nDONE:\nN40M30\n", "PROC SUB9\nN10DEF REAL W\nN20W=1\nN30IF W>0 GOTOF SKIP\nSKIP:\nN40RET\n",
 ],
 "h": [
  "0 BEGIN PGM T MM\n1 FN 9: IF +Q1 EQU +0 GOTO LBL 1\n2 LBL 1\n3 LBL 0\n4 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 FN 11: IF +Q1 GT +0 GOTO LBL \"A\"\n2 LBL \"A\"\n3 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 LBL 1\n2 LBL 0\n3 CALL LBL 1 REP 3\n4 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 FN 14: ERROR= 1000\n2 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 FN 16: F-PRINT TNC:\\MASKE.A / TNC:\\PROT.TXT\n2 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 FN 18: SYSREAD Q1 = ID20 NR1\n2 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 QS1 = \"ABC\"\n2 Q2 = STRLEN ( SRC_QS1 )\n3 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 Q1 = SIN ( 30 )\n2 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 Q1 = SQRT 4\n2 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 FN 0: Q1 = +5\n2 FN 1: Q2 = +Q1 + +3\n3 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 FN 12: IF +Q1 LT +Q2 GOTO LBL 1\n2 LBL 1\n3 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 FN 10: IF +Q1 NE +Q2 GOTO LBL 1\n2 LBL 1\n3 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 FN 17: SYSWRITE ID990 NR4 IDX3 = 0\n2 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 Q3 = STRCOMP( SRC_QS1 SEA_QS2 )\n2 END PGM T MM\n",
  "0 BEGIN PGM T MM\n1 CALL PGM SUB1\n2 END PGM T MM\n",
 ],
 "pim": [
  "$IF P1 == 0\nG0 X0\n$ELSEIF P1 == 1\nG0 X1\n$ELSE\nG0 X2\n$ENDIF\nM30\n", "$GOTO N10\nN10 M30\n", "$FOR P1 = 1, 5, 1\n$ENDFOR\nM30\n",
  "P1=0\n$WHILE P1 < 3\nP1=P1+1\n$ENDWHILE\nM30\n", "$SWITCH P1\n$CASE 1\nG0 X1\n$BREAK\n$DEFAULT\nG0 X2\n$ENDSWITCH\nM30\n",
  "N10 G0 X1\nN20 G0 X2\n$RPT N10, N20 NR3\nM30\n", "G0 X10 NR3\nM30\n", "#MSG [\"HELLO\"]\nM30\n", "#ERROR [\"BAD\"]\nM30\n",
  "#WARNING [\"CAREFUL\"]\nM30\n", "P1 = SIN [30]\nM30\n", "P1 = ABS [-2]\nM30\n", "N10G0X0Y0\nM30\n", "P1 = V.G.TOOL\nM30\n",
  "$DO\nP1=P1+1\n$ENDDO P1 > 3\nM30\n",
 ],
}

CASES = [(extension, program) for extension, programs in FORMS.items() for program in programs]


def _syntax(program: str, extension: str):
    result = check_text(program, f"form.{extension}", Settings())
    return result, [d for d in result.diagnostics if d.rule in ("core.syntax", "core.dialect-unsupported")]


@pytest.mark.parametrize("extension, program", CASES, ids=[f"{extension}:{program.splitlines()[0][:40]}" for extension, program in CASES])
def test_the_form_is_read(extension, program):
    result, problems = _syntax(program, extension)
    assert result.dialect == DIALECTS[extension]
    assert problems == []


@pytest.mark.parametrize("jump, missing_alarms", [("GOTOF", True), ("GOTOB", True), ("GOTO", True), ("GOTOC", False)])
def test_a_sinumerik_jump_to_a_missing_label_alarms_except_gotoc(jump, missing_alarms):
    result = check_text(f"G0 X0\n{jump} NOWHERE\nM30\n", "jump.mpf", Settings())
    alarms = [d for d in result.diagnostics if d.rule == "core.label-not-found" and d.status is Status.VIOLATED]
    assert bool(alarms) is missing_alarms


@hypothesis_settings(max_examples=30, deadline=None)
@given(number=st.integers(1, 9999), x=st.integers(-500, 500), extension=st.sampled_from(["nc", "mpf"]))
def test_a_block_number_written_against_the_next_word_is_the_block_number(number, x, extension):
    """N10G1X5: a jump finds it by its number, and the words after it are the block's."""
    jump = f"GOTO {number}" if extension == "nc" else f"GOTOF N{number}"
    result, problems = _syntax(f"G0 X0 Y0\n{jump}\nG0 X1\nN{number}G1X{x}F100\nM30\n", extension)
    assert problems == []
    assert not [d for d in result.diagnostics if d.rule == "core.label-not-found"]


@hypothesis_settings(max_examples=30, deadline=None)
@given(function=st.sampled_from(["SIN", "COS", "ABS", "SQRT", "TRUNC", "ROUND"]), blanks=st.text(" ", min_size=0, max_size=3),
       value=st.integers(0, 90))
def test_a_blank_before_a_functions_parenthesis_is_read_sinumerik(function, blanks, value):
    result, problems = _syntax(f"R1={function}{blanks}({value})\nG0 X=R1\nM30\n", "mpf")
    assert problems == []


@hypothesis_settings(max_examples=30, deadline=None)
@given(function=st.sampled_from(["SIN", "COS", "ABS", "SQRT", "FIX", "ROUND"]), blanks=st.text(" ", min_size=0, max_size=3),
       value=st.integers(0, 90))
def test_a_blank_before_a_functions_bracket_is_read_iso(function, blanks, value):
    result, problems = _syntax(f"#1={function}{blanks}[{value}.]\nG0 X#1\nM30\n", "nc")
    assert problems == []
