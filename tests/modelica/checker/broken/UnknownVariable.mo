// expect: 10: part.lenght resolves to nothing
// expect: 11: Units.Metric resolves to nothing
// expect: 13: k resolves to nothing
within ValidLib;
model UnknownVariable "A misspelt component of a component, enumeration literal and iterator"
  ValidLib.Part part;
  Real x;
  Real y[3];
equation
  x = part.lenght;
  part.choice = Units.Metric;
  for i in 1:3 loop
    y[k] = i;
  end for;
end UnknownVariable;
