within DEMLink.Components;
model Material "A bulk material: a database entry, optionally with some values replaced"
  extends DEMLink.Interfaces.PartialComponent(name = "gravel", final kind = "material", final exchanged = false,
    final declInts = fill(0, 0), final declReals = {DEMLink.Functions.optional(density),
    DEMLink.Functions.optional(youngsModulus), DEMLink.Functions.optional(poissonRatio),
    DEMLink.Functions.optional(restitution), DEMLink.Functions.optional(slidingFriction),
    DEMLink.Functions.optional(rollingFriction)}, final declStrings = {databaseName});
  parameter String databaseName = "gravel"
    "Database material: sand, gravel, hard_coal, brown_coal, iron_ore, potash, corn, wheat (data/materials.csv); empty: custom";
  parameter Modelica.Units.SI.Density density = -1 "Particle (solid) density; negative: the database's";
  parameter Modelica.Units.SI.ModulusOfElasticity youngsModulus = -1 "DEM Young's modulus; negative: the database's";
  parameter Real poissonRatio(unit = "1") = -1 "Poisson ratio [1]; negative: the database's";
  parameter Real restitution(unit = "1") = -1 "Coefficient of restitution [1]; negative: the database's";
  parameter Real slidingFriction(unit = "1") = -1 "Coulomb friction coefficient [1]; negative: the database's";
  parameter Real rollingFriction(unit = "1") = -1 "Rolling friction coefficient [1]; negative: the database's";
  annotation (Documentation(info = "<html><p>Other components name a material by this component's
<code>name</code>. The database (the materials of the coupling paper, section 4.2) holds
starting values, not calibrations; see docs/materials.md.</p></html>"));
end Material;
