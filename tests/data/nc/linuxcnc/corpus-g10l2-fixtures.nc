(Two studs in a gang fixture: G56 and G57 set by G10 L2, M12x1.75 on each)
(style: LinuxCNC lathe shop program with fixture offsets in the program)
(G10 L2 / G56 / G57: LinuxCNC G-code manual, G10 L2 and coordinate systems)
(G91 chamfer and G90.1 arc centres: LinuxCNC G-code manual, G91, G90.1, G2 with I K)
G18 G7 G21 G90 G40 G80 G94
G10 L2 P3 X0 Z-40
G10 L2 P4 X0 Z-95
T1 M6 G43
G97 S1200 M3
G56
G0 X14 Z2
G1 X10.5 Z0.5 F120
G91 G1 X1.5 Z-0.75
G90 G1 Z-18
G90.1 G2 X15 Z-19.5 I7.5 K-18 F80
G91.1
G0 X20 Z5
T3 M6 G43
G97 S500 M3
G0 X14 Z4
G76 P1.75 Z-16 I-1 J0.25 K1.07 R2 Q29.5 H1
G57
G0 X14 Z4
G76 P1.75 Z-16 I-1 J0.25 K1.07 R2 Q29.5 H1
G54
G0 X40 Z60
M5
M30
