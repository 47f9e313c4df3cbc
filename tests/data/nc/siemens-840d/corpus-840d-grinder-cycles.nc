%_N_THREAD_ROLL_MPF
;$PATH=/_N_WKS_DIR/_N_ROLL_WPD
; 840D thread-rolling/grinding cell program as the machine's HMI screens write it: a test
; switch, the machine maker's set-up cycles (not on this disk: skipped with warnings), then
; the thread passes on the spindle of the part (M1=, S1=); spindle 3 is the wheel
TEST=1
_APPROACH("KRUG1",1,0,1,0,0,0,0,0,0,0)
_THREAD_SETUP("NORTON_400_20",1,0,2,15,17.693,6,0,1,-4,-55,0,0,12,8,60,"RAVNO","PROBA")
N10 G18 G90 G95 G54
N20 M3=3 S3=1500              ; the wheel spindle
N30 M1=3 S1=400               ; the part spindle
N40 G0 X26 Z5
N50 R1=23.4
N60 LOOP1: X=R1
N70 G33 Z-30 K3
N80 G0 X26
N90 Z5
N100 G4 S2                    ; two revolutions between passes
N110 R1=R1-0.4
N120 IF R1>=22.2 GOTOB LOOP1
N130 M3=5
N140 M30
