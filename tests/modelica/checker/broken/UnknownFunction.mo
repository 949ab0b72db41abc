// expect: 8: call of ValidLib.scal: no such function
// expect: 9: call of ValidLib.scale: ValidLib.scale has no input gain
within ValidLib;
model UnknownFunction "A misspelt function and a misspelt named argument"
  Real y;
  Real z;
equation
  y = ValidLib.scal(1);
  z = ValidLib.scale(1, gain = 2);
end UnknownFunction;
