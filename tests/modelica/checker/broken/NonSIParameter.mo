// expect: 9: parameter mass: Real without a unit
// expect: 10: Modelica.SIunits.Length: Modelica.SIunits does not exist in Modelica 4.0.0
// expect: 11: parameter temperature: Modelica.Units.NonSI.Temperature_degC is outside Modelica.Units.SI
// expect: 12: parameter ratio: Real without a unit
// expect: 13: parameter empty: Real without a unit
// expect: 14: parameter values: Real without a unit
within ValidLib;
model NonSIParameter "No unit, MSL 3's units, a non-SI type, a short type without unit, an empty unit, a false marker"
  parameter Real mass = 1 "[kg] in the description is no unit";
  parameter Modelica.SIunits.Length length = 1;
  parameter Modelica.Units.NonSI.Temperature_degC temperature = 20;
  parameter Plain ratio = 0.5;
  parameter Real empty(unit = "") = 1;
  parameter Real values[:] = {1, 2} annotation (__DEMLink(mixedUnits = false));
  type Plain = Real "No unit";
end NonSIParameter;
