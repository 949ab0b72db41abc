within DEMLink.Components;
model ParticleSource "Inserts particles into a box or disc at a steady rate (particles or mass per second)"
  extends DEMLink.Interfaces.PartialComponent(name = "source", final kind = "particle_source", final exchanged = true,
    final declInts = {seed, Integer(region) - 1, Integer(sizes) - 1},
    final declReals = cat(1, centre, if region == DEMLink.Types.SourceRegion.Disc then normal else halfExtents,
    {rMin, rMax, DEMLink.Functions.optional(ratePerSecond), DEMLink.Functions.optional(rateKgPerSecond)}, velocity,
    {startTime, DEMLink.Functions.optional(stopTime), discRadius, thickness},
    if sizes == DEMLink.Types.SizeDistribution.Normal then {mean, std} else {weightAtMin, weightAtMax},
    {if mod(i, 2) == 1 then discreteRadii[div(i + 1, 2)] else discreteWeights[div(i, 2)] for i in 1:2 * size(discreteRadii, 1)}),
    final declStrings = {material, attachedTo});
  parameter String material = "gravel" "Material name";
  parameter DEMLink.Types.SourceRegion region = DEMLink.Types.SourceRegion.Box "Box or disc";
  parameter Modelica.Units.SI.Position centre[3] = {0, 0, 1} "Region centre (body frame when attached)";
  parameter Modelica.Units.SI.Length halfExtents[3] = {0.2, 0.2, 0.1} "Half edge lengths of the box"
    annotation (Dialog(enable = region == DEMLink.Types.SourceRegion.Box));
  parameter Real normal[3] = {0, 0, 1} "Disc axis"
    annotation (Dialog(enable = region == DEMLink.Types.SourceRegion.Disc));
  parameter Modelica.Units.SI.Radius discRadius = 0.2 "Disc radius (>= the largest particle radius)"
    annotation (Dialog(enable = region == DEMLink.Types.SourceRegion.Disc));
  parameter Modelica.Units.SI.Length thickness = 0 "Extent along the axis (0: a thin disc)"
    annotation (Dialog(enable = region == DEMLink.Types.SourceRegion.Disc));
  parameter DEMLink.Types.SizeDistribution sizes = DEMLink.Types.SizeDistribution.Uniform "Radius distribution";
  parameter Modelica.Units.SI.Radius rMin = 0.01 "Smallest radius (Constant: every radius)";
  parameter Modelica.Units.SI.Radius rMax = 0.01 "Largest radius";
  parameter Real weightAtMin = 1 "Relative pdf at rMin (Linear)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Linear));
  parameter Real weightAtMax = 1 "Relative pdf at rMax (Linear)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Linear));
  parameter Modelica.Units.SI.Radius mean = 0.01 "Mean radius (Normal)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Normal));
  parameter Modelica.Units.SI.Length std = 0.002 "Standard deviation of the radius (Normal)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Normal));
  parameter Modelica.Units.SI.Radius discreteRadii[:] = fill(0.01, 0) "Radii (Discrete)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Discrete));
  parameter Real discreteWeights[size(discreteRadii, 1)] = fill(1, size(discreteRadii, 1)) "Relative probabilities (Discrete)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Discrete));
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
  annotation (Documentation(info = "<html><p>A box or disc region (docs/sources.md) with one of
the schema's radius distributions: one radius, uniform, linear pdf, truncated normal or
discrete (the solver paper's distributions). Declared through the generic layout of the C ABI
(docs/c_abi.md, particle_source).</p></html>"));
end ParticleSource;
