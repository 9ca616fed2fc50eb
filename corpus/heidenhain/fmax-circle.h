0  BEGIN PGM FMAXARC MM
1  ; A RETURN AROUND THE PART PROGRAMMED AS CIRCLES
2  ; Defect: FMAX on the circle blocks makes them rapid arcs; the arc about CC X+50 Y+50
3  ; with radius 70 stays clear of the blank, but a rapid arc's path is not checked: unknown
4  BLK FORM 0.1 Z X+0 Y+0 Z-20
5  BLK FORM 0.2  X+100  Y+100  Z+0
6  TOOL CALL 5 Z S4000 F300
7  L  Z+50 R0 FMAX M3
8  L  X-20 Y+50 R0 F1000
9  L  Z-5 R0 FMAX
10 CC X+50 Y+50
11 C  X+120 Y+50 DR- FMAX
12 L  Z+50 R0 FMAX
13 END PGM FMAXARC MM
