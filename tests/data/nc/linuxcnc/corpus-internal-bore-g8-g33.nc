(Internal M36x1.5 in a bored hole, radius mode, flank infeed by shifting Z, coolant)
(style: shop program in G8 radius mode; sources: LinuxCNC G-code manual G8, G33, M8/M9)
G18 G8 G21 G90 G94
T4 M6 G43
S800 M3 M8
G0 X16 Z2
o1 repeat [3]
  G0 X[#<_x> + 0.5]
  G1 Z-30 F90
  G0 X[#<_x> - 0.2] Z2
  G0 X[#<_x> + 0.2]
o1 endrepeat
T5 M6 G43
S300 M3
#<minor> = 17.25
#<h> = 0.92
#<n> = 0
o2 while [#<n> LT 8]
  #<n> = [#<n> + 1]
  #<d> = [#<h> * SQRT[#<n> / 8]]
  G0 X16.5 Z[3 - #<d> * TAN[29.5]]
  G0 X[#<minor> - 0.5 + #<d>]
  G33 Z-26 K1.5
  G0 X16.5
o2 endwhile
G0 Z10 M9
M5
M2
