(3/4-10 UNC external in inch, entry and exit tapers on both ends)
(style: ngcgui inch thread form output; sources: LinuxCNC G-code manual G20, G76 E and L3; ASME B1.1)
G18 G7 G20 G90 G94
T3 M6 G43
S400 M3
G0 X0.85 Z0.2
G76 P0.1 Z-1.0 I-0.05 J0.008 K0.0613 R1.5 Q29.5 H2 E0.1 L3
G0 X1.2 Z1.5
M5
M2
