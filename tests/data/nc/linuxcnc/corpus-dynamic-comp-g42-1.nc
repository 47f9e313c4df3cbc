( LinuxCNC lathe: M16x1.5 stud finished under dynamic compensation, in the style of the )
( conversational lathe generators that write G41.1/G42.1 with the insert's D and L words )
G18 G21 G7 G90 G95 G40
T1 M6
G96 S180 D3000 M3
G0 X22 Z2
( face under G41.1: the nose to the +Z side of the face )
G41.1 D1.6 L2 G1 Z0 F0.1
X-1.6
G40 G0 Z2
G0 X22 Z2
( finishing pass: a 0.8 mm nose radius insert, D = 2 r, orientation L2 )
G42.1 D1.6 L2 G0 X12 Z1
G1 X16 Z-1 F0.12
Z-24
X19
G3 X21 Z-25 I0 K-1
G1 Z-30
G40 G0 X26 Z2
( thread: compensation off )
T2 M6
G97 S700 M3
G0 X18 Z4
G76 P1.5 Z-22 I-0.25 J0.2 R1.5 K0.92 Q29.5 H2 E0 L0
G0 X40 Z40
M2
