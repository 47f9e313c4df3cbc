%_N_FLANGE_TAP_MPF
;$PATH=/_N_MPF_DIR
; face, centre drill and tap M10 on the axis: rigid tapping G331/G332 (840D)
N10 G18 G90 G95 G54 DIAMON
N20 T="FACE" D1 M6
N30 G96 S180 LIMS=3000 M3
N40 G0 X52 Z0
N50 G1 X-1 F0.12
N60 G0 X100 Z100
N70 T="DRILL_8_5" D1 M6
N80 G97 S1200 M3
N90 G0 X0 Z3
N100 G1 Z-25 F0.1           ; tap drill 8.5
N110 G0 Z3
N120 G0 X100 Z100
N130 T="TAP_M10" D1 M6
N140 G0 X0 Z5
N150 SPOS=0                 ; the spindle in position control
N160 G331 Z-20 K1.5 S300    ; tap in
N170 G332 Z5 K1.5           ; and out, the spindle reversed
N180 G0 X100 Z100
N190 M30
