G7
#40=0
o20 while [1]
#40=[#40+1]
o21 if [#40 EQ 1]
G0 X1
o21 elseif [#40 EQ 2]
G0 X2
o22 if [1]
o20 continue
o22 endif
G0 X99
o21 else
o20 break
o21 endif
G0 X[10+#40]
o20 endwhile
G0 X[100+#40]
