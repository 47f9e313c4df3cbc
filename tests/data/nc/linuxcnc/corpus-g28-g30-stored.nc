(Tool change at a stored position: G30.1 stores it, G30 returns there; G28.1 and G28 home)
(G92.2 suspends and G92.3 restores a G92 shift for the second thread)
(style: hobby lathe program with a manual tool change point; sources: LinuxCNC G-code manual)
(G28.1, G30.1, G92, G92.2, G92.3; G33 spindle-synchronised motion)
G18 G7 G21 G90 G94
G0 X60 Z80
G30.1
G0 X0 Z100
G28.1
T3 M6
G30
S400 M3
G0 X22 Z3
#<pass> = 0
o2 while [#<pass> LT 5]
  #<pass> = [#<pass> + 1]
  G0 X[20 - 0.25 * #<pass>] Z3
  G33 Z-14 K1.5
  G0 X22
  G0 Z3
o2 endwhile
G92 Z-20
G92.2
G0 X22 Z-30
G33 Z-38 K1.5
G0 X24
G92.3
G0 X22 Z3
G33 Z-6 K1.5
G0 X24
G92.1
G30
G28
M5
M2
