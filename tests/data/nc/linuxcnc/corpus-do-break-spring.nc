(Passes until the depth is reached: do loop with break, pass kind chosen by if/elseif/else)
(style: course exercise with constant-area passes; sources: LinuxCNC O Codes do/while, break, if/elseif/else)
G18 G7 G21 G90 G94
T3 M6
S450 M3
#<total> = 1.3
#<first> = 0.35
#<done> = 0
#<n> = 0
o10 do
  #<n> = [#<n> + 1]
  o11 if [#<n> EQ 1]
    #<done> = #<first>
  o11 elseif [#<done> + 0.05 GE #<total>]
    #<done> = #<total>
  o11 else
    #<done> = [#<first> * SQRT[#<n>]]
    o12 if [#<done> GT #<total>]
      #<done> = #<total>
    o12 endif
  o11 endif
  G0 X26 Z3
  G0 X[24 - 2 * #<done>]
  G33 Z-20 K2
  G0 X26
  o13 if [#<done> GE #<total>]
    o10 break
  o13 endif
o10 while [#<n> LT 50]
G0 X[24 - 2 * #<total>] Z3
G33 Z-20 K2
G0 X30 Z20
M5
M2
