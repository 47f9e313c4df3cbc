(External thread macro as a gmoccapy lathe macro writes it: reads the current position and units)
(style: gmoccapy/QtDragon lathe macros; sources: LinuxCNC manual Predefined Named Parameters, G76)
o<ext_thread> sub
  #<major> = #1
  #<pitch> = #2
  #<length> = #3
  #<start_z> = #<_z>
  o1 if [#<_metric> EQ 0]
    (abort, metric only)
  o1 endif
  G0 X[#<major> + 2]
  G76 P#<pitch> Z[#<start_z> - #<length>] I-1 J[#<pitch> / 8] K[#<pitch> * 0.6134] R1.5 Q30 H1
  G0 Z#<start_z>
o<ext_thread> endsub
G18 G7 G21 G90 G94
T3 M6 G43
S500 M3
G0 X22 Z3
o<ext_thread> call [20] [1.5] [18]
G0 X22 Z-22
o<ext_thread> call [18] [1] [8]
G0 X40 Z40
M5
M2
