within DEMLink.Components;
model ParticleSource "Inserts particles into a box at a steady rate (particles or mass per second)"
  extends DEMLink.Interfaces.PartialComponent(name = "source", final kind = "particle_source", final exchanged = true,
    final declInts = {seed}, final declReals = cat(1, centre, halfExtents, {rMin, rMax,
    DEMLink.Functions.optional(ratePerSecond), DEMLink.Functions.optional(rateKgPerSecond)}, velocity,
    {startTime, DEMLink.Functions.optional(stopTime)}), final declStrings = {material, attachedTo});
  parameter String material = "gravel" "Material name";
  parameter Modelica.Units.SI.Position centre[3] = {0, 0, 1} "Box centre (body frame when attached)";
  parameter Modelica.Units.SI.Length halfExtents[3] = {0.2, 0.2, 0.1} "Half edge lengths of the box";
  parameter Modelica.Units.SI.Radius rMin = 0.01 "Smallest radius (radii uniform in [rMin, rMax]; equal: constant)";
  parameter Modelica.Units.SI.Radius rMax = 0.01 "Largest radius";
  parameter Real ratePerSecond = 1000 "Particles per second [1/s] (negative: use rateKgPerSecond)";
  parameter Real rateKgPerSecond = -1 "Mass per second [kg/s] (negative: use ratePerSecond)";
  parameter Modelica.Units.SI.Velocity velocity[3] = {0, 0, 0} "Initial particle velocity";
  parameter Modelica.Units.SI.Time startTime = 0 "Insertion starts";
  parameter Modelica.Units.SI.Time stopTime = -1 "Insertion stops (negative: never)";
  parameter Integer seed = 1 "Random seed";
  parameter String attachedTo = "" "Rigid body whose mesh the box moves with (empty: fixed)";
  Modelica.Blocks.Interfaces.IntegerOutput countTotal(start = 0, fixed = true) "Particles inserted since the start"
    annotation (Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Modelica.Blocks.Interfaces.RealOutput massTotal(unit = "kg", start = 0, fixed = true) "Mass inserted since the start"
    annotation (Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Modelica.Blocks.Interfaces.IntegerOutput shortfallTotal(start = 0, fixed = true)
    "Requested but not placed since the start (no room in the box)" annotation (Placement(transformation(extent = {{100, -30}, {120, -10}})));
  Modelica.Blocks.Interfaces.RealOutput massInterval(unit = "kg", start = 0, fixed = true) "Mass inserted in the last interval"
    annotation (Placement(transformation(extent = {{100, -70}, {120, -50}})));
protected
  Integer status(start = 0, fixed = true);
  Integer counts[3](each start = 0, each fixed = true);
  Real masses[3](each start = 0, each fixed = true);
algorithm
  when sample(0, tc) then
    (status, counts, masses) := DEMLink.Functions.External.particleSourceRead(client, 0);
    DEMLink.Functions.checkExchange(client, status);
    countTotal := counts[2];
    massTotal := masses[2];
    shortfallTotal := counts[3];
    massInterval := masses[1];
  end when;
  annotation (Documentation(info = "<html><p>The box source of the C ABI with radii uniform
in [rMin, rMax]. Disc regions and other size distributions exist in scene files
(docs/sources.md) but not yet in the C ABI's declaration layout.</p></html>"));
end ParticleSource;
