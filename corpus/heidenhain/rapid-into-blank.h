0  BEGIN PGM BLANK MM
1  ; no project file: the BLK FORM alone is the stock the rapids are judged against
2  BLK FORM 0.1 Z X+0 Y+0 Z-20
3  BLK FORM 0.2  X+100  Y+100  Z+0
4  TOOL CALL 2 Z S4000
5  L  Z+50 R0 FMAX M3
6  L  X+30  Y+30 R0 FMAX
7  L  Z-5 R0 FMAX
8  L  Z+50 R0 FMAX
9  ; a drilling cycle whose surface is written 10 mm too low: its set-up clearance lies inside the blank
10 CYCL DEF 200 DRILLING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q201=-10 ;DEPTH ~
    Q206=+150 ;FEED RATE FOR PLNGNG ~
    Q202=+5 ;PLUNGING DEPTH ~
    Q210=+0 ;DWELL TIME AT TOP ~
    Q203=-10 ;SURFACE COORDINATE ~
    Q204=+20 ;2ND SET-UP CLEARANCE
11 L  X+70  Y+70 R0 FMAX M99
12 L  Z+50 R0 FMAX M30
13 END PGM BLANK MM
