(PathPilot conversational output style: Thread - Internal, two starts by Z shift)
(Description: M24x3 P1.5 two-start internal, G30 tool change position)
(Units = MM, Work offset = G54)
N100 G7 G18 G21 G90 G40 G80 G94
N101 G54
N102 G30
(Tool 5 - internal threading)
N103 T0505
N104 G97 S450 M3
N105 M8
(Start 1)
N106 G0 X21.5 Z6
N107 G76 P3 Z-20 I0.5 J0.3 K1.84 R1.5 Q29.5 H1
(Start 2: shifted by the pitch 1.5)
N108 G0 X21.5 Z7.5
N109 G76 P3 Z-20 I0.5 J0.3 K1.84 R1.5 Q29.5 H1
N110 G0 Z10
N111 M9
N112 M5
N113 G30
N114 M30
