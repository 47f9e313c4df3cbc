(Face, turn to size under constant surface speed, then thread M24x2)
(style: LinuxCNC sim/lathe example program; G96 D limits the spindle speed)
(sources: LinuxCNC G-code manual G96 S D, G95, G97, G2 R, G76)
G18 G7 G21 G90 G40 G80
T1 M6 G43
G96 S180 D2500 M3
G95
G0 X30 Z0.2
G1 X-0.4 F0.12
G0 Z2
#<dia> = 29
o1 while [#<dia> GT 24.5]
  #<dia> = [#<dia> - 1.5]
  o2 if [#<dia> LT 24]
    #<dia> = 24
  o2 endif
  G0 X#<dia> Z2
  G1 Z-30 F0.2
  G0 X[#<dia> + 1] Z2
o1 endwhile
G0 X20 Z1
G1 X24 Z-1 F0.1
G1 Z-28
G2 X28 Z-30 R2
G1 X31
G94
G0 X30 Z40
T3 M6 G43
G97 S600 M3
G0 X26 Z4
G76 P2 Z-24 I-1 J0.3 K1.23 R2 Q29.5 H1 E2 L2
G0 X40 Z60
M5
M30
