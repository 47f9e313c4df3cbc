(Two threads cut by a gmoccapy-style macro that saves the caller's modes with M73, called through o[..] by tool number)
(style: LinuxCNC nc_files/macros/lathe turning and threading macros [M73, #<_x>, #<_imperial>], a shop main program in G20 G91 G8)
(sources: LinuxCNC manual M70-M73 [M70 save, M72 restore, M71 forget], O Codes indirection o[..] call, G76; M6 stops the spindle: M3 after each tool change)
G18 G20 G8 G90 G94
F12 S500 M3
o103 sub
  M73 (the caller's G20, G94, F, S, G8 come back at endsub)
  G7 G21 G95 G90
  M6 T3 G43
  G97 S[#3] M3
  #<start_z> = [#<_z> + 2]
  G0 X[#1 + 2] Z#<start_z>
  G76 P[#2] Z-12 I-1 J0.2 K[1.0825 * #2] R1.5 Q29.5 H1 E[#2] L2
  G0 Z#<start_z>
o103 endsub
o104 sub
  M73
  G7 G21 G95 G90
  M6 T4 G43
  G97 S[#3] M4
  G0 X[#1 - 2] Z2
  G76 P[#2] Z-10 I1 J0.15 K[1.3 * #2] R2 Q29.5 H2
  G0 Z2
o104 endsub
#<tool> = 3
G0 X0.6 Z0.2
o[100 + #<tool>] call [16] [1.5] [600]
G1 X0.7 Z0.1 (after the call: inch, per minute and radius again, as the caller set them)
M70 (save the main program's modes)
G91 G7
G1 X0.2 Z-0.05 (incremental, X a diameter)
M72 (back to G90 G8)
M71 (and forget them)
#<tool> = 4
G0 X0.25 Z0.1
o[100 + #<tool>] call [12] [1.0] [800]
G1 X0.2 Z0
M5
M2
