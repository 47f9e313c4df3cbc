(Six short studs in a gang plate, one per work offset G54..G59.3; one G76 each)
(style: production lathe program with one work offset per station)
(sources: LinuxCNC G-code manual, G54-G59.3 and G10 L2 in the program)
G18 G7 G21 G90 G94
G10 L2 P5 Z-30
G10 L2 P6 Z-45
G10 L2 P7 Z-60
G10 L2 P8 Z-75
G10 L2 P9 Z-90
T3 M6 G43
S600 M3
o<station> sub
  G0 X12 Z3
  G76 P1.25 Z-8 I-1 J0.2 K0.77 R1.5 Q30 H0
  G0 X16 Z5
o<station> endsub
G58
o<station> call
G59
o<station> call
G59.1
o<station> call
G59.2
o<station> call
G59.3
o<station> call
G54
G0 X30 Z20
M5
M2
