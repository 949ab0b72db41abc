within DEMLink.Components;
model SingleParticle "One sphere"
  extends DEMLink.Interfaces.PartialComponent(name = "particle", final kind = "single_particle", final exchanged = false,
    final declInts = fill(0, 0), final declReals = cat(1, position, velocity, {diameter}), final declStrings = {material});
  parameter String material = "gravel" "Material name";
  parameter Modelica.Units.SI.Position position[3] = {0, 0, 0.5} "Initial centre";
  parameter Modelica.Units.SI.Velocity velocity[3] = {0, 0, 0} "Initial velocity";
  parameter Modelica.Units.SI.Diameter diameter = 0.02 "Diameter";
end SingleParticle;
