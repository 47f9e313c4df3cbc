G7
o2 sub
o3 if [#1 GT 0]
#<_s>=[#<_s>+#1]
o2 call [#1-1]
o3 endif
o2 endsub
#<_s>=0
o2 call [5]
G0 X#<_s>
