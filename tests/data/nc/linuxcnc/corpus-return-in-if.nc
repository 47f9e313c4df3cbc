(ngcgui-style thread subroutine that checks its arguments and returns early: o100 return inside o100 if)
(issue 27's example: rs274 runs it, the if label is local to the sub and return names the sub)
(sources: LinuxCNC O Codes chapter, subroutines, return, if; ngcgui subroutine conventions)
o100 sub
  (#1 major diameter, #2 pitch, #3 length)
  o100 if [#2 LE 0]
    (MSG, pitch must be positive)
    o100 return [-1]
  o100 endif
  o101 if [#3 LE 0]
    o100 return [-2]
  o101 endif
  G0 X[#1 + 2] Z3
  G76 P#2 Z[-#3] I-1 J[#2 * 0.2] K[#2 * 0.6134] R2 Q29.5 H1
  G0 X[#1 + 6] Z10
o100 endsub [1]
G18 G7 G21 G90 G94
T3 M6 G43
S500 M3
o100 call [20] [2.5] [25]
#<first> = #<_value>
o100 call [20] [0] [25]
#<second> = #<_value>
o100 call [12] [1.75] [14]
G0 X[40 + #<first> + #<second>] Z30
M5
M2
