(Spindle with a relief neck: G71.1 roughs without pockets, G71.2 takes the pocket, G70 finishes; thread in a while loop)
(style: the LinuxCNC manual's advice for G7x.1 then G7x.2 [D1.0 then D0.5], a hobby shop program)
(sources: LinuxCNC G-code manual G71 G72 [G71.1, G71.2 and pockets], G70, G33, O-codes while)
G18 G7 G21 G90 G40
G95
o300 sub
  G0 X10 Z1
  G1 Z0
  G1 X16 Z-3
  G1 Z-20
  G3 X12 Z-22 I-2 K0
  G1 Z-26
  G2 X16 Z-28 I2 K0
  G1 Z-40
  G1 X30 A1
  G1 Z-48
  G1 X36
o300 endsub
T1 M6 G43
G97 S900 M3
G0 X38 Z3
G71.1 Q300 X38 Z3 D1 I1.2 R0.5 F0.2
G71.2 Q300 X38 Z3 D0.5 I1.2 R0.5 F0.15
G70 Q300 X38 Z3 D0.5 P1 F0.08
G0 X40 Z20
T3 M6 G43
G97 S500 M3
#<pitch> = 1.5
#<depth> = 0.92
#<pass> = 1
o310 while [#<pass> LE 6]
  #<x> = [16 - 2 * #<depth> * SQRT[#<pass> / 6]]
  G0 X18 Z4
  G0 X#<x>
  G33 Z-19 K#<pitch>
  G0 X18
  #<pass> = [#<pass> + 1]
o310 endwhile
G0 X40 Z20
M5
M30
