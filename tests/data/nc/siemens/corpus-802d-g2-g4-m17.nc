; 802D pin M24x2 with a radius at the shoulder; the thread passes in a
; subprogram that ends with M17, the pass diameter in R1
N10 G18 G90 G95 G54
N20 T1 D1                    ; roughing and finishing tool
N30 G96 S160 LIMS=2500 M3 M8
N40 G0 X26 Z2
N50 G1 X24 Z0 F0.15
N60 Z-28
N70 G2 X30 Z-31 CR=3         ; R3 at the shoulder
N80 G1 X36
N90 G0 X80 Z80
N100 T3 D1                   ; grooving tool 3 mm
N110 G97 S500 M3
N120 G0 X30 Z-28
N130 G1 X20.5 F0.05
N140 G4 F0.5                 ; dwell half a second at the bottom
N150 G0 X30
N160 G0 X80 Z80
N170 T4 D1                   ; threading tool
N180 G97 S600 M3
N190 R1=23.2
N200 GEW24
N210 R1=22.6
N220 GEW24
N230 R1=22.0
N240 GEW24
N250 R1=21.55
N260 GEW24 P2                ; the last depth twice
N270 G0 X80 Z80
N280 M30
