(Left-hand M16x1.5 LH with the insert upside down and the spindle in reverse, M4)
(threads from the relief groove towards the chuck-free end: left-hand thread cut towards +Z)
(style: course exercise for left-hand threads on a rear tool post; sources: LinuxCNC manual M4, G33)
G18 G7 G21 G90 G94
T3 M6 G43
S350 M4
#<major> = 16
#<depth> = 0.92
#<n> = 0
o10 do
  #<n> = [#<n> + 1]
  #<cut> = [#<depth> * SQRT[#<n> / 6]]
  G0 X[#<major> - 2 * #<cut>] Z-25
  G33 Z2 K1.5
  G0 X[#<major> + 2]
  G0 Z-25
o10 while [#<n> LT 6]
G0 X30 Z20
M5
M2
