; 802D shaft M20x1.5, thread passes by R parameters and a label loop
; (no cycle: the passes are written out as the 802D parameter programming
; examples do)
N5 G18 G90 G95 G54
N10 T1 D1
N15 G96 S160 LIMS=2500 M3 M8
N20 G0 X24 Z0.2
N25 G1 X-1.6 F0.15
N30 G0 X19.9 Z2
N35 G1 Z-28 F0.2
N40 X24
N45 G0 X80 Z80
N50 T2 D1                   ; 60 deg threading insert
N55 G97 S700 M3
N60 R1=20 R2=1.5 R3=0.92    ; nominal, pitch, depth
N65 R4=0.3 R5=0             ; depth step, depth reached
AGAIN: R5=R5+R4
N75 IF R5>R3 GOTOF FINISH
N80 G0 X=R1-2*R5 Z5
N85 G33 Z-25 K=R2
N90 G0 X25
N95 Z5
N100 GOTOB AGAIN
FINISH: G0 X=R1-2*R3 Z5
N110 G33 Z-25 K=R2
N115 G0 X25
N120 X80 Z80 M9
N125 M30
