G7
G0 X1
  #1 = [2 + #<UndefinedName>]
