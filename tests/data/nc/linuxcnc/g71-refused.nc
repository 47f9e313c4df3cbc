(LinuxCNC 2.9 G71 roughing over the o100 contour, then G70 finishing: refused by name)
G18 G7 G21 G90
M3 S1000
G0 X30 Z2
o100 sub
G1 X10 Z0
G1 X10 Z-10
G1 X20 Z-20
G1 X30
o100 endsub
G71 Q100 X30 Z2 D1 I0.5 R0.5 F0.2
G70 Q100
M2
