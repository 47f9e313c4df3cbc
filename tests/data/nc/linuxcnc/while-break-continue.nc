G7
#10=0
o400 while [#10 LT 9]
#10=[#10+1]
G0 X#10
o401 if [[#10 MOD 2] EQ 0]
o400 continue
o401 endif
o402 if [#10 GE 5]
o400 break
o402 endif
G0 X[100+#10]
o400 endwhile
G0 X[1000+#10]
