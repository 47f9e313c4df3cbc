(ngcgui lathe macro style: a named thread sub with positional arguments and named locals)
(1/2-13 UNC external, inch)
o<lathe_thread> sub
  #<tpi>      = #1   (threads per inch)
  #<major>    = #2   (major diameter)
  #<length>   = #3   (thread length from Z0)
  #<firstcut> = #4   (first depth, diameter)
  #<passes_r> = #5   (degression)
  #<springs>  = #6
  #<pitch>    = [1 / #<tpi>]
  #<depth>    = [0.6134 * #<pitch> * 2]   (full depth, diameter)
  G0 X[#<major> + 0.1] Z0.2
  G76 P#<pitch> Z[-#<length>] I-0.05 J#<firstcut> K#<depth> R#<passes_r> Q29.5 H#<springs> E[#<pitch> * 2] L2
  G0 X[#<major> + 0.2]
o<lathe_thread> endsub

G18 G7 G20 G90 G40 G80 G94
G30
(T1 turn the major)
T1 M6 G43
G96 D2000 S500 M3
G95 F0.006
G0 X0.6 Z0.1
G1 Z0.005 F0.004
X-0.04
G0 Z0.1 X0.55
G1 Z-1.2 F0.008
G0 X0.6 Z0.1
X0.5
G1 Z-1.2
X0.6
G0 Z0.1
(T3 threading)
T3 M6 G43
G97 S800 M3
o<lathe_thread> call [13] [0.5] [1.0] [0.012] [1.5] [1]
M5
G30
M2
