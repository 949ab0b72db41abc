// expect: 5: type of part: ValidLib.Prt resolves to no class
// expect: 6: base class ValidLib.Parts resolves to no class
within ValidLib;
model UnknownClass "A misspelt component type and base class"
  ValidLib.Prt part;
  extends ValidLib.Parts;
end UnknownClass;
