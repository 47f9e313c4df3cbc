(gmoccapy/QtDragon lathe macro style: internal thread, #<_...> state read back)
(M30x1.5 internal in a 27 mm bore, metric or inch by #<_metric>)
o<int_thread> sub
  #<pitch>  = #1
  #<minor>  = #2      (bore diameter, the crest)
  #<depth>  = #3      (radial depth)
  #<zend>   = #4
  (#<_x> reads the current X as a radius, even in G7: doubled to the diameter)
  #<start_x> = [#<_x> * 2]
  G76 P#<pitch> Z#<zend> I[#<minor> - #<start_x>] J0.45 K[2 * #<depth>] R2 Q30 H1
  G0 X#<start_x>
o<int_thread> endsub

G18 G7 G90 G40 G80 G94
o10 if [#<_metric> EQ 0]
  G21 (the macro works in mm)
o10 endif
T4 M6 G43
G97 S900 M3
M8
G0 X26 Z3
(bore to the thread minor)
G1 Z0 F100
G95 F0.1
X27 Z-0.5
Z-22
X26
G0 Z3
T5 M6 G43
G97 S500 M3
G0 X25 Z4
o<int_thread> call [1.5] [27.0] [0.92] [-18]
G0 Z20
M9 M5
M2
