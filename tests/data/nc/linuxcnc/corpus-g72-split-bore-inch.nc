(Inch end cap: G72.1 faces the front, G72.2 cuts the face recess it left, G70 finishes; 1-8 UNC thread on the hub)
(style: a LinuxCNC shop program in G20 with numbered contour subs, two G7x.n passes as the manual suggests)
(sources: LinuxCNC G-code manual G72 [G72.1, G72.2], G70, G20, G76; ASME B1.1 1-8 UNC)
G18 G7 G20 G90 G40
G95
o400 sub
  G1 X2.6 Z-0.7
  G1 X2.2
  G1 X2.2 Z-0.45
  G1 X1.8 Z-0.6
  G1 X1.6 Z-0.45
  G1 X1.0 C0.02
  G1 Z-0.05
  G1 X0.9 Z0
  G1 X0
o400 endsub
T1 M6 G43
G97 S800 M3
G0 X2.7 Z0.1
G72.1 Q400 X2.7 Z0.1 D0.02 I0.05 R0.02 F0.008
G72.2 Q400 X2.7 Z0.1 D0.01 I0.04 R0.02 F0.006
G70 Q400 X2.7 Z0.1 D0.01 F0.004
G0 X3 Z1
T3 M6 G43
G97 S400 M3
G0 X1.1 Z0.2
G76 P0.125 Z-0.4 I-0.05 J0.008 K0.0767 R2 Q29.5 H1
G0 X3 Z1
M5
M30
