%_N_TWO_THREADS_MPF
;$PATH=/_N_MPF_DIR
; 840D shaft with two M20x1.5 threads 40 mm apart: the same passes twice, the second
; thread placed by TRANS; the tool change position in machine coordinates (SUPA)
N10 G18 G90 G95 G54 DIAMON
N20 T="THREAD_60" D1 M6
N30 SUPA G0 X200 Z150
N40 G97 S700 M3 M8
N50 TRANS Z0
N60 PASS_M20(19.25)
N70 PASS_M20(18.9)
N80 PASS_M20(18.6)
N90 PASS_M20(18.35)
N100 PASS_M20(18.16)
N110 TRANS Z-40                 ; the second thread
N120 PASS_M20(19.25)
N130 PASS_M20(18.9)
N140 PASS_M20(18.6)
N150 PASS_M20(18.35)
N160 PASS_M20(18.16)
N170 TRANS                      ; frame off
N180 SUPA G0 X200 Z150 M9
N190 M30
