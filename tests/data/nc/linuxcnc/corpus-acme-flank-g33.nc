(1-6 ACME by G33 passes with compound infeed along the 14.5 degree flank, inch)
(style: shop program for an Acme screw; sources: LinuxCNC G33 and TAN in degrees; ASME B1.5 depth 0.5P+0.01)
G18 G7 G20 G90 G94
T3 M6
S200 M3
#<p> = [1 / 6]
#<depth> = [0.5 * #<p> + 0.01]
#<n> = 0
o1 while [#<n> LT 10]
  #<n> = [#<n> + 1]
  #<d> = [#<depth> * #<n> / 10]
  G0 X1.1 Z[0.25 - #<d> * TAN[14.5]]
  G0 X[1 - 2 * #<d>]
  G33 Z-2.5 K#<p>
  G0 X1.1
o1 endwhile
G0 X1.5 Z2
M5
M2
