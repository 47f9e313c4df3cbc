(G33 chain: straight thread then a 45 deg pull-out in the same synchronised motion)
(hand-written shop style, M12x1.75, five passes by a numbered sub with arguments)
o100 sub
  (#1 = pass diameter, #2 = pitch)
  G0 X14 Z3
  G0 X#1
  G33 Z-15 K#2
  G33 X[#1 + 2 * #2] Z[-15 - #2] K#2
  G0 X16
o100 endsub

G18 G7 G21 G90 G40 G80 G94
T3 M6 G43
G97 S700 M3
o100 call [11.2] [1.75]
o100 call [10.8] [1.75]
o100 call [10.5] [1.75]
o100 call [10.0] [1.75]
o100 call [9.85] [1.75]
G0 Z20
M5
M2
