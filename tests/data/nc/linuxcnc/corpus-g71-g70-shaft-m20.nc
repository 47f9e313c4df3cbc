(Shaft with an M20x2 thread: rough the contour with G71, finish it with G70, thread with G76)
(style: LinuxCNC nc_files lathe_g70_71_demo.ngc, a shop program around one o100 contour)
(sources: LinuxCNC G-code manual G70, G71 G72 [Q contour sub, D I R, A fillet, C chamfer], G42, G76)
G18 G7 G21 G90 G40 G80
G95
o100 sub
  G0 X14 Z2
  G1 Z0
  G1 X20 Z-3
  G1 Z-28
  G1 X24 A0.8
  G1 Z-40
  G3 X32 Z-44 I0 K-4
  G1 X38 C1
  G1 Z-60
  G1 X44
o100 endsub
T1 M6 G43
G96 S200 D2800 M3
G0 X46 Z3
G71 Q100 X46 Z3 D0.3 I1.5 R0.5 F0.25
G0 X60 Z30
T2 M6 G43
G96 S250 D3200 M3
G42
G70 Q100 X46 Z3 D0.3 E0 P2 F0.1
G40
G0 X60 Z30
T3 M6 G43
G97 S600 M3
G0 X24 Z4
G76 P2 Z-26 I-2 J0.25 K2.45 R2 Q29.5 H1 E2 L2
G0 X60 Z30
M5
M30
