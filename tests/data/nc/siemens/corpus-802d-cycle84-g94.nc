; 802D adapter: M16x1.5 outside with CYCLE97, M8 tapped in the centre with
; CYCLE84; the centre drill in feed per minute (G94)
N10 G18 G90 G95 G54
N20 T1 D1                    ; turning
N30 G96 S180 M3
N40 G0 X18 Z2
N50 G1 X16 Z0 F0.15
N60 Z-24
N70 X20
N80 G0 X80 Z80
N90 T2 D1                    ; drill 6.8 on the axis
N100 G97 S1200 M3
N110 G94 F96                 ; feed per minute for the drill
N120 G0 X0 Z2
N130 G1 Z-18
N140 G0 Z2
N150 G95                     ; feed per revolution again
N160 G0 X80 Z80
N170 T3 D1                   ; tap M8x1.25
N180 G97 S300 M3
N190 G0 X0 Z5
N200 CYCLE84(5,0,2,-14,,0,3,,1.25,0,300,300)
N210 G0 X80 Z80
N220 T4 D1                   ; threading tool
N230 G97 S800 M3
N240 G0 X18 Z4
N250 CYCLE97(1.5,,0,-20,16,16,4,0,0.92,0.05,30,0,5,1,1,1)
N260 G0 X80 Z80
N270 M30
