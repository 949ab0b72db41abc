// expect: 6: part: ValidLib.Part has no element lenght
// expect: 7: x: Real has no attribute unti
// expect: 9: choice: ValidLib.Units has no attribute unit
within ValidLib;
model UnknownModifier "Modifiers that name nothing"
  ValidLib.Part part(lenght = 2);
  Real x(unti = "m");
  // An enumeration has start and fixed (section 4.9.5) but no unit.
  ValidLib.Units choice(start = ValidLib.Units.SI, fixed = true, unit = "m");
end UnknownModifier;
