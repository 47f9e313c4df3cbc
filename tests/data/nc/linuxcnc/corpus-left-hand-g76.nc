(Left-hand external thread M24x2 LH: G76 cut from the shoulder towards +Z, exit taper)
(course exercise style: the tool starts beside the relief groove and runs off the end)
G18 G7 G21 G90 G40 G80 G94
T1 M6 G43
G96 D2500 S200 M3
G95 F0.2
G0 X26 Z2
G1 Z0 F0.1
X-1.6
G0 Z2 X23.95
G1 Z-30 F0.2
X26
G0 Z2
T2 M6 G43
G97 S800
G0 X26 Z-28
G1 X21 F0.05
G0 X26
T3 M6 G43
G97 S500 M3
(start in the groove, cut towards +Z)
G0 X25 Z-27
G76 P2 Z1 I-0.5 J0.6 K2.45 R2 Q29.5 H1 E1 L2
G0 X30 Z5
M5
M2
