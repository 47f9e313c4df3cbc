(A thread pass written once in incremental moves and called per depth: G91 inside the sub)
(style: hand-written shop subroutine; sources: LinuxCNC G-code manual G91, G33, O-codes call)
G18 G7 G21 G90 G94
T3 M6
S500 M3
o<inc_pass> sub
  (#1 infeed on diameter from the start X24)
  G91
  G0 X[-2 - #1]
  G33 Z-22 K1.5
  G0 X[2 + #1]
  G0 Z22
  G90
o<inc_pass> endsub
G0 X24 Z4
o<inc_pass> call [0.3]
o<inc_pass> call [0.6]
o<inc_pass> call [0.85]
o<inc_pass> call [1.05]
o<inc_pass> call [1.2]
o<inc_pass> call [1.2]
G0 X30 Z30
M5
M2
