%_N_CELL_M30_MPF
;$PATH=/_N_MPF_DIR
; 840D cell program: the pass table, macros and the thread cycle come from the machine's
; definition files (THR_GUD.DEF, THR_MAC.DEF) and its cycle _THR_PASS
DEF INT NN
N10 G18 G90 G95 G54 DIAMON
N20 TEST=1
N30 T="THREAD_60" D1 M6
N40 G97 S500 M3 COOLANT_ON
N50 FOR NN=0 TO THR_PASSES
N60   _THR_PASS(THR_DIA[NN], 2, "THREAD_60")
N70 ENDFOR
N80 G0 X150 Z100 M9
N90 M30
