; 802D internal M32x1.5 (bore d30.4 before threading), CYCLE97 VARI 4
N10 G18 G90 G95 G54
N20 T4 D1                   ; boring bar
N30 G96 S140 M3 M8
N40 G0 X30 Z2
N50 G1 Z-22 F0.1
N60 X28
N70 G0 Z50
N80 T5 D1                   ; internal threading tool
N90 G97 S500 M3
N100 G0 X28 Z6
N110 CYCLE97(1.5,,0,-20,30,30,3,0,0.812,0.05,30,0,4,0,4,1)
N120 G0 Z50
N130 M30
