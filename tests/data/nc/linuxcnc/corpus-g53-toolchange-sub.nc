(Every tool change through one subroutine that goes to a safe point in machine coordinates)
(style: LinuxCNC lathe program with a tool change macro; sources: LinuxCNC G-code manual G53, M6, O-codes)
o<tc> sub
  G53 G0 X120
  G53 G0 Z150
  T#1 M6 G43
  S#2 M3
o<tc> endsub
G18 G7 G21 G90 G94
o<tc> call [1] [900]
G0 X32 Z2
G1 Z-40 F120
G0 X34 Z2
G1 X30 Z0 F100
G1 Z-40
G0 X36
o<tc> call [3] [450]
G0 X32 Z4
G76 P2 Z-36 I-1 J0.3 K1.23 R2 Q29.5 H1
o<tc> call [1] [900]
M5
M2
