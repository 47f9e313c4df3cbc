(Turn and thread a stud after touching the tools off in the program: G10 L1/L10/L11, G43, G43.1, G43.2, G42.1 D0)
(style: a LinuxCNC shop program that sets its tool table itself, as the G10 L10 and G43.1 manual pages show)
(sources: LinuxCNC G-code manual G10 L1, G10 L10, G10 L11, G43, G43.1, G43.2, G41.1/G42.1; the tip follows the program whatever the offsets)
G18 G7 G21 G90 G95 G40
G10 L1 P1 X0 Z0 R0 (tool 1: turning, zero nose radius)
T1 M6 G43
S800 M3
G0 X40 Z2
G10 L10 P1 Z2 (touched off at the face: the current point reads Z2)
G42.1 D0 L2 (dynamic compensation with a zero diameter: moves as programmed)
G1 X36 Z0 F0.2
G1 Z-30
G1 X40
G40
G0 Z2
G43.1 Z0.05 (a wear shift on the fly)
G1 X35 Z0 F0.15
G1 Z-30
G0 X40
G49
G0 Z5
G10 L11 P3 Z0 (tool 3 from the G59.3 frame)
T3 M6 G43 H3
G43.2 H5 (plus tool 5's offsets)
S500 M3
G0 X37 Z4
G76 P1.5 Z-26 I-1 J0.2 K0.92 R2 Q29.5 H1 E1.5 L2
G49
G0 X60 Z40
M5
M30
