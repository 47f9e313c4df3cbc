G7
o100 sub
#<loc>=[#1*2]
o100 endsub [#<loc>]
o200 sub
o200 endsub
o30 sub
o30 return [#1+1]
G0 X999
o30 endsub
G0 X#<_value>
o100 call [21]
G0 X#<_value>
G0 X#<_value_returned>
o200 call
G0 X#<_value>
G0 X#<_value_returned>
o30 call [4]
G0 X#<_value>
