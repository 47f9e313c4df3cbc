(A sub with a return value picks the pass count; repeat adds spring passes by G33)
(M10x1.5 external, course style)
o<passes> sub
  (#1 depth, #2 first cut: passes of a sqrt law)
  o1 return [FIX[[#1 / #2] * [#1 / #2]] + 1]
o<passes> endsub

G18 G7 G21 G90 G40 G80 G94
T3 M6 G43
G97 S700 M3
o<passes> call [0.92] [0.3]
#<n> = #<_value>
#<k> = 1
o20 do
  #<d> = [0.3 * SQRT[#<k>]]
  o21 if [#<d> GT 0.92]
    #<d> = 0.92
  o21 endif
  G0 X12 Z3
  G0 X[10 - 2 * #<d>]
  G33 Z-14 K1.5
  G0 X12
  #<k> = [#<k> + 1]
o20 while [#<k> LE #<n>]
o30 repeat [2]
  G0 X12 Z3
  G0 X8.16
  G33 Z-14 K1.5
  G0 X12
o30 endrepeat
M5
M2
