(Flange with a hub: face the step down with G72 in radius mode, finish with G70, thread the hub M30x1.5)
(style: LinuxCNC nc_files lathe_g7x_quadrants.ngc, a G72 face contour run from the outside in)
(sources: LinuxCNC G-code manual G72 [passes along X], G70, G8, G76)
G18 G8 G21 G90 G40
G95
T1 M6 G43
G97 S700 M3
G0 X32 Z2
o200 sub
  G1 X31 Z-18
  G1 X19 A1
  G1 X17 Z-16
  G1 X15 C0.5
  G1 Z-1.5
  G1 X13.5 Z0
  G1 X0
o200 endsub
G72 Q200 X32 Z2 D0.25 I1.2 R0.4 F0.2
G70 Q200 X32 Z2 D0.25 F0.08
G0 X40 Z20
T3 M6 G43
G97 S450 M3
G0 X17 Z4
G76 P1.5 Z-14 I-1.5 J0.12 K0.92 R1.5 Q29.5 H2 E1 L2
G0 X40 Z20
M5
M30
