(Tapered G33 thread on a 1:10 cone on diameter, metric, with a straight lead-in in the chain)
(Each pass: a straight G33 then a tapered G33 continuing the same motion)
G18 G7 G21 G90 G40 G80 G94
T1 M6 G43
G96 D2500 S200 M3
G95 F0.2
G0 X25 Z2
G1 X20 Z0 F0.12
Z-5
X22.5 Z-30
X25
G0 Z2
T3 M6 G43
G97 S500 M3
#<i> = 0
o60 while [#<i> LT 6]
  #<d> = [0.2 + #<i> * 0.2]
  G0 X24 Z4
  G0 X[20 - #<d>]
  G33 Z-5 K1.5
  G33 X[22.5 - #<d>] Z-30 K1.5
  G0 X26
  #<i> = [#<i> + 1]
o60 endwhile
G0 Z10
M5
M2
