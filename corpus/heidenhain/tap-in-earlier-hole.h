0  BEGIN PGM TAPEARLIER MM
1  ; the second operation of a series: the BLK FORM is the raw blank, and the holes
2  ; were drilled and spot-faced to Z-6 by the program before this one. A tap needs a
3  ; hole, and this program drills none: its approach to Q203 + Q200 = Z-4 goes down a
4  ; hole the blank does not show, which is not checked (unknown), not a crash
5  BLK FORM 0.1 Z X+0 Y+0 Z-20
6  BLK FORM 0.2  X+100  Y+100  Z+0
7  TOOL CALL 3 Z S400
8  L  Z+50 R0 FMAX M3
9  L  X+30  Y+30 R0 FMAX
10 CYCL DEF 207 RIGID TAPPING NEW ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q201=-12 ;DEPTH ~
    Q239=+1.5 ;THREAD PITCH ~
    Q203=-6 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE
11 L  X+30  Y+30 R0 FMAX M99
12 L  X+70  Y+70 R0 FMAX M99
13 L  Z+50 R0 FMAX M30
14 END PGM TAPEARLIER MM
