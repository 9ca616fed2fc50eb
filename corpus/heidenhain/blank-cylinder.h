0  BEGIN PGM BLANKCYL MM
1  ; A round blank R25 about Z (BLK FORM CYLINDER), not a lathe bar: the rapid at Y100
2  ; passes far from it, the one from X35 Y0 to X0 Y40 cuts across it with the tool's side.
3  ; ncverify: tool 1 radius 5 length 60
4  BLK FORM CYLINDER Z R25 L100
5  TOOL CALL 1 Z S2000
6  L  X+40 Y+0 Z+50 R0 FMAX M3
7  L  Z-5 R0 FMAX
8  L  X+35 Y+100 R0 FMAX
9  L  X+35 Y+0 R0 FMAX
10 L  X+0 Y+40 R0 FMAX
11 L  Z+50 R0 FMAX
12 END PGM BLANKCYL MM
