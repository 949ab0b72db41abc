// expect: 6: unit "m/s^2" is no unit expression
// expect: 7: unit "N m" is no unit expression
within ValidLib;
model BadUnit "Unit strings outside the unit-expression grammar"
  parameter Modelica.Units.SI.Length ok = 1;
  parameter Real acceleration(unit = "m/s^2") = 9.81;
  Real torque[3](each unit = "N m");
end BadUnit;
