(CNC course exercise style: manual threading with G33 in a while loop, flank infeed)
(M16x2 external, 29.5 deg compound by shifting Z each pass)
#<major> = 16
#<pitch> = 2
#<depth> = 1.227
#<n> = 1
#<passes> = 9
G18 G7 G21 G90 G40 G80 G94
T1 M6 G43
G96 D3000 S150 M3
G95 F0.2
G0 X18 Z2
G1 X15.96 F0.1
Z-24
X18
G0 Z2
T3 M6 G43
G97 S500 M3
o100 while [#<n> LE #<passes>]
  #<d> = [#<depth> * SQRT[#<n> / #<passes>]]
  #<zs> = [3 - #<d> * TAN[29.5]]
  G0 X[#<major> + 2] Z#<zs>
  G0 X[#<major> - 2 * #<d>]
  G33 Z-20 K#<pitch>
  G0 X[#<major> + 2]
  #<n> = [#<n> + 1]
o100 endwhile
(spring pass)
G0 Z[3 - #<depth> * TAN[29.5]]
G0 X[#<major> - 2 * #<depth>]
G33 Z-20 K#<pitch>
G0 X20
G0 Z20
M5
M2
