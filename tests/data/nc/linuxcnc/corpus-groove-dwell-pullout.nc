(Relief groove with a dwell, then G33 passes with a 45 degree pull-out into the groove)
(style: course exercise for thread run-out; sources: LinuxCNC G-code manual G4 P seconds, G33 chains)
G18 G7 G21 G90 G94
T2 M6
S600 M3
G0 X22 Z-24.5
G1 X16.8 F40
G4 P0.5
G0 X22
G0 Z-25.5
G1 X16.8
G4 P0.5
G0 X22
T3 M6
S400 M3
(#<k> counts the passes from 0 without being set first: rs274 creates it when the line names it)
o1 repeat [6]
  #<k> = [#<k> + 1]
  G0 X22 Z3
  G0 X[20 - 0.4 * SQRT[#<k>] * 1.6]
  G33 Z-22 K2.5
  G33 X[22 - 0.4 * SQRT[#<k>] * 1.6] Z-24 K2.5
  G0 X24
o1 endrepeat
G0 X30 Z30
M5
M2
