(Three-start M20x6 P2 by an o-word loop over the starts, each start shifted by the pitch)
(course style, the lead 6 in G76 P, the start Z moved by 2 each time)
#<lead> = 6
#<starts> = 3
#<s> = 0
G18 G7 G21 G90 G40 G80 G94
T3 M6 G43
G97 S250 M3
o50 while [#<s> LT #<starts>]
  G0 X22 Z[12 + #<s> * #<lead> / #<starts>]
  G76 P#<lead> Z-25 I-1 J0.4 K2.45 R1.5 Q29.5 H0
  #<s> = [#<s> + 1]
o50 endwhile
G0 X30 Z30
M5
M2
