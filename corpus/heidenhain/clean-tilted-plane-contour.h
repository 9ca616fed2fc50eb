0  BEGIN PGM TILTRL MM
1  ; a boss on the side face, milled in a tilted working plane (positions there are not
2  ; modelled): the compensation is built up on the straight L block that writes RL, so
3  ; the arc after it is no compensation start; the shift is reset before PLANE RESET,
4  ; an order the manual prescribes for cycle 19, not for the PLANE function
5  BLK FORM 0.1 Z X-60 Y-40 Z-30
6  BLK FORM 0.2  X+60  Y+40  Z+0
7  TOOL CALL 4 Z S3500
8  L  Z+150 R0 FMAX M3
9  CYCL DEF 7.0 DATUM SHIFT
10 CYCL DEF 7.1 X+60
11 CYCL DEF 7.2 Z-12
12 PLANE SPATIAL SPA+0 SPB+90 SPC+0 TURN MB MAX FMAX
13 L  X-18 Y+6 R0 FMAX
14 L  Z+5 R0 FMAX
15 L  Z-3 R0 F250
16 L  X-12 Y+0 RL F400
17 CC X+0 Y+0
18 C  X+12 Y+0 DR-
19 L  X+22 Y+0
20 L  X+26 Y+6 R0
21 L  Z+60 R0 FMAX
22 CYCL DEF 7.0 DATUM SHIFT
23 CYCL DEF 7.1 X+0
24 CYCL DEF 7.2 Z+0
25 PLANE RESET TURN MB MAX FMAX
26 L  Z+150 R0 FMAX M30
27 END PGM TILTRL MM
