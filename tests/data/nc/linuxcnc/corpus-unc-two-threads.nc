(Two UNC threads on one stud, inch: one sub called twice with tpi, major, start and end)
(ngcgui style named sub; 3/8-16 and 1/4-20)
o<stud_thread> sub
  #<tpi> = #1
  #<maj> = #2
  #<zs> = #3
  #<ze> = #4
  #<p> = [1 / #<tpi>]
  G0 X[#<maj> + 0.1] Z#<zs>
  G76 P#<p> Z#<ze> I-0.05 J[0.2 * #<p>] K[1.2268 * #<p>] R1.5 Q29.5 H1 E#<p> L2
  G0 X[#<maj> + 0.2]
o<stud_thread> endsub

G18 G7 G20 G90 G40 G80 G94
T1 M6 G43
G96 D2000 S400 M3
G95 F0.005
G0 X0.45 Z0.1
G1 Z0 F0.003
X-0.03
G0 Z0.1 X0.2495
G1 Z-0.6 F0.005
X0.3745
Z-1.6
X0.45
G0 Z0.1
T3 M6 G43
G97 S900 M3
o<stud_thread> call [20] [0.25] [0.1] [-0.5]
o<stud_thread> call [16] [0.375] [-0.5] [-1.5]
G0 Z1
M5
M2
