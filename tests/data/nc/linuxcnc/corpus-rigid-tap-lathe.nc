(Centre hole tapped M8x1.25 on the lathe axis with rigid tapping, then an external thread)
(style: LinuxCNC manual G33.1 example moved to the lathe's Z axis)
(sources: LinuxCNC G-code manual, G33.1 rigid tapping: X/Z target, K pitch, spindle reverses)
G18 G7 G21 G90 G94
T6 M6
S300 M3
G0 X0 Z5
G33.1 Z-15 K1.25
G0 Z20
T3 M6
S450 M3
G0 X26 Z4
G76 P2 Z-22 I-1 J0.3 K1.23 R1.5 Q29.5 H2 E1 L2
G0 X40 Z40
M5
M2
