( LinuxCNC lathe: M22x1.5 stud finished with tool nose radius compensation )
( the nose radius and orientation set in the tool table by the program, G10 L1 )
G18 G21 G7 G90 G95
G10 L1 P6 R0.4 Q2 ( T6: VNMG R0.4, orientation 2: the tip -Z -X of the nose )
T6 M6
G96 S150 D2500 M3
G0 X26 Z3
G41 G1 Z0 F0.1 ( face under G41: the nose to the +Z side of the face )
X-0.8
G40 G0 Z2
G0 X26 Z2
G42 G0 X17 Z1
G1 X21.8 Z-1.4 F0.1
Z-18
G2 X25.8 Z-20 I2 K0 ( R2 fillet into the collar )
G1 X28
G40 G0 X32 Z2
T3 M6
G97 S600 M3
G0 X24 Z4
G76 P1.5 Z-16 I-0.3 J0.3 R1.5 K0.92 Q29.5 H1 E0 L0
G0 X40 Z40
M2
