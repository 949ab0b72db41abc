// expect: 7: parameter mass: Real without a unit
// expect: 8: Modelica.SIunits.Length: Modelica.SIunits does not exist in Modelica 4.0.0
// expect: 9: parameter temperature: Modelica.Units.NonSI.Temperature_degC is outside Modelica.Units.SI
// expect: 10: parameter ratio: Real without a unit
within ValidLib;
model NonSIParameter "A Real parameter without unit, the MSL 3 units package, a non-SI type, a short type without unit"
  parameter Real mass = 1 "[kg] in the description is no unit";
  parameter Modelica.SIunits.Length length = 1;
  parameter Modelica.Units.NonSI.Temperature_degC temperature = 20;
  parameter Plain ratio = 0.5;
  type Plain = Real "No unit";
end NonSIParameter;
