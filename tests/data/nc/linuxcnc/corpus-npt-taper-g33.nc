(1/2-14 NPT external pipe thread: tapered G33 passes, taper 1:16 on diameter)
(G33 K is the lead along the move in LinuxCNC: the z lead is K times the cosine of the taper)
G18 G7 G20 G90 G40 G80 G94
T1 M6 G43
G96 D1500 S400 M3
G95 F0.006
G0 X0.9 Z0.1
(turn the 1:16 taper on diameter, 0.84 at Z0)
G1 X0.8338 Z0.05 F0.004
X0.84 Z0
X0.8838 Z-0.7
X0.9
G0 Z0.1
T3 M6 G43
G97 S400 M3
#<pitch> = [1 / 14]
#<h> = [0.8 * #<pitch>]
#<k> = 1
o200 repeat [7]
  #<dx> = [2 * #<h> * SQRT[#<k> / 7]]
  G0 X1.0 Z0.2
  (on the 1:16 cone: 0.8275 at Z0.2, 0.88375 at Z-0.7)
  G0 X[0.8275 - #<dx>]
  G33 X[0.88375 - #<dx>] Z-0.7 K#<pitch>
  G0 X1.0
  #<k> = [#<k> + 1]
o200 endrepeat
G0 Z1
M5
M2
