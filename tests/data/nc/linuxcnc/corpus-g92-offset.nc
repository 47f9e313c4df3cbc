(Second part in the same setup: G92 shifts Z so the same code threads a part 50 mm further out)
(hobby shop style, G10 L20 to set G55 from the current position)
G18 G7 G21 G90 G40 G80 G94
T3 M6 G43
G97 S500 M3
G0 X24 Z5
(part 1, G54)
G76 P1.5 Z-18 I-1 J0.3 K1.84 R1.5 Q29.5 H0
G0 Z60
(part 2: the current Z60 is Z5 of the second part)
G92 Z5
G0 X24 Z5
G76 P1.5 Z-18 I-1 J0.3 K1.84 R1.5 Q29.5 H0
G92.1
G0 X30 Z80
(part 3 with G10 L20: here X30 Z80 becomes G55 X24 Z5)
G10 L20 P2 X24 Z5
G55
G76 P1.5 Z-18 I-1 J0.3 K1.84 R1.5 Q29.5 H0
G54
G0 X40 Z100
M5
M2
