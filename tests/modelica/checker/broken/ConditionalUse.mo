// expect: 8: u: u is a conditional component (declared with if): it may only be modified and used in connect equations
within ValidLib;
model ConditionalUse "A conditional input used in an equation instead of a connect"
  parameter Boolean use_u = false;
  Modelica.Blocks.Interfaces.RealInput u if use_u;
  Real x;
equation
  x = u;
end ConditionalUse;
