// expect: 5: part: ValidLib.Part has no element lenght
// expect: 6: x: Real has no attribute unti
within ValidLib;
model UnknownModifier "Modifiers that name nothing"
  ValidLib.Part part(lenght = 2);
  Real x(unti = "m");
end UnknownModifier;
