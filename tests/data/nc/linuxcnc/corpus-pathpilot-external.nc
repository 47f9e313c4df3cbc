(PathPilot conversational output style: Thread - External)
(Description: 3/4-10 UNC, G30 tool change position)
(Units = Inch, Work offset = G54)
N100 G7 G18 G20 G90 G40 G80 G94
N101 G54
N102 G30
(Tool 3 - threading)
N103 T0303
N104 G97 S700 M3
N105 M8
N106 G0 X0.85 Z0.25
(Thread - External - 3/4-10)
(Major Dia = 0.7500, Minor Dia = 0.6273, Pitch = 0.1000)
(Passes = 8, Spring = 1, Infeed Angle = 29.5)
N107 G76 P0.1000 Z-1.0000 I-0.0500 J0.0400 K0.1227 R2.0 Q29.5 H1 E0.1000 L2
N108 G0 X0.85 Z0.25
N109 M9
N110 M5
N111 G30
N112 M30
