G7
#<a>=7
#1=9
o10 sub
#<a>=3
#1=4
#31=31
G0 X[#<a>+#1]
o10 endsub
o10 call [1]
G0 X#<a>
G0 X#1
G0 X#31
o10 call [2]
