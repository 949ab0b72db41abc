// expect: 6: syntax error at column 11: unexpected ';'
within ValidLib;
model SyntaxError "A binding without its expression"
  Real x;
equation
  x = 1 + ;
end SyntaxError;
