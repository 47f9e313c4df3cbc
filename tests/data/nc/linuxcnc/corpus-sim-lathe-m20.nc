(LinuxCNC sim/lathe demo style: M20x2.5 external, face, turn, chamfer, groove, G76)
(stock 25 mm bar, Z0 at the finished face, tool table with zero offsets)
G18 G7 G21 G90 G40 G80 G94
G54
(--- T1 right-hand turning tool ---)
T1 M6 G43
G96 D2500 S180 M3
M8
G95 F0.15
G0 X27 Z2
G1 Z0.2
X-1.6
G0 Z2
X26
G1 Z0
X-1.6
G0 Z1 X23
G1 Z-32 F0.25
G0 X25 Z1
X20.5
G1 Z-32
G0 X25 Z1
X16
G1 Z0 F0.12
X19.94 Z-1.97
Z-32
X24
G2 X25 Z-32.5 R0.5
G1 Z-40
G0 X30
G53 G0 X0 Z0
(--- T2 grooving tool 3 mm, left edge ---)
T2 M6 G43
G97 S900
G0 X26 Z-32
G1 X16.8 F0.05
G4 P0.3
G0 X26
(--- T3 60 deg threading insert ---)
T3 M6 G43
G97 S600 M3
G0 X22 Z5
G76 P2.5 Z-29 I-1 J0.4 K3.0678 R1.5 Q29.5 H2 E1.5 L2
G0 X30 Z5
M9
M5
G53 G0 X0 Z0
M2
