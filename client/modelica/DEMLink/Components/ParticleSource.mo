within DEMLink.Components;
model ParticleSource "Inserts particles into a box or disc at a steady rate (particles or mass per second)"
  extends DEMLink.Interfaces.PartialComponent(name = "source", final kind = "particle_source", final exchanged = true,
    final declInts = {seed, Integer(region) - 1, Integer(sizes) - 1},
    final declReals = cat(1, centre, if region == DEMLink.Types.SourceRegion.Disc then normal else halfExtents,
    {rMin, rMax, DEMLink.Functions.optional(ratePerSecond), DEMLink.Functions.optional(rateKgPerSecond)}, velocity,
    {startTime, DEMLink.Functions.optional(stopTime), discRadius, thickness},
    if sizes == DEMLink.Types.SizeDistribution.Normal then {mean, std} else {weightAtMin, weightAtMax},
    {if mod(i, 2) == 1 then discreteRadii[div(i + 1, 2)] else discreteWeights[div(i, 2)] for i in 1:2 * size(discreteRadii, 1)}),
    final declStrings = {material, attachedTo, clumpTemplate});
  parameter String material = "gravel" "Material name";
  parameter DEMLink.Types.SourceRegion region = DEMLink.Types.SourceRegion.Box "Box or disc";
  parameter Modelica.Units.SI.Position centre[3] = {0, 0, 1} "Region centre (body frame when attached)";
  parameter Modelica.Units.SI.Length halfExtents[3] = {0.2, 0.2, 0.1} "Half edge lengths of the box"
    annotation (Dialog(enable = region == DEMLink.Types.SourceRegion.Box));
  parameter Real normal[3](each unit = "1") = {0, 0, 1} "Disc axis"
    annotation (Dialog(enable = region == DEMLink.Types.SourceRegion.Disc));
  parameter Modelica.Units.SI.Radius discRadius = 0.2 "Disc radius (>= the largest particle radius)"
    annotation (Dialog(enable = region == DEMLink.Types.SourceRegion.Disc));
  parameter Modelica.Units.SI.Length thickness = 0 "Extent along the axis (0: a thin disc)"
    annotation (Dialog(enable = region == DEMLink.Types.SourceRegion.Disc));
  parameter DEMLink.Types.SizeDistribution sizes = DEMLink.Types.SizeDistribution.Uniform "Radius distribution";
  parameter Modelica.Units.SI.Radius rMin = 0.01 "Smallest radius (Constant: every radius)";
  parameter Modelica.Units.SI.Radius rMax = 0.01 "Largest radius";
  parameter Real weightAtMin(unit = "1") = 1 "Relative pdf at rMin (Linear)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Linear));
  parameter Real weightAtMax(unit = "1") = 1 "Relative pdf at rMax (Linear)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Linear));
  parameter Modelica.Units.SI.Radius mean = 0.01 "Mean radius (Normal)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Normal));
  parameter Modelica.Units.SI.Length std = 0.002 "Standard deviation of the radius (Normal)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Normal));
  parameter Modelica.Units.SI.Radius discreteRadii[:] = fill(0.01, 0) "Radii (Discrete)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Discrete));
  parameter Real discreteWeights[size(discreteRadii, 1)](each unit = "1") = fill(1, size(discreteRadii, 1)) "Relative probabilities (Discrete)"
    annotation (Dialog(enable = sizes == DEMLink.Types.SizeDistribution.Discrete));
  parameter Real ratePerSecond(unit = "1/s") = 1000 "Particles per second [1/s] (negative: use rateKgPerSecond)";
  parameter Real rateKgPerSecond(unit = "kg/s") = -1 "Mass per second [kg/s] (negative: use ratePerSecond)";
  parameter Modelica.Units.SI.Velocity velocity[3] = {0, 0, 0} "Initial particle velocity";
  parameter Modelica.Units.SI.Time startTime = 0 "Insertion starts";
  parameter Modelica.Units.SI.Time stopTime = -1 "Insertion stops (negative: never)";
  parameter Integer seed = 1 "Random seed";
  parameter String attachedTo = "" "Rigid body whose mesh the box moves with (empty: fixed)";
  parameter String clumpTemplate = "" "Name of a ClumpTemplate component: clumps of its shape instead of spheres (empty: spheres)";
  parameter Boolean use_rate_in = false "Rate from the input rate_in instead of the fixed rate"
    annotation (Evaluate = true, choices(checkBox = true), Dialog(group = "Run-time inputs"));
  parameter Boolean use_on_in = false "Insertion switched on and off by the input on_in"
    annotation (Evaluate = true, choices(checkBox = true), Dialog(group = "Run-time inputs"));
  Modelica.Blocks.Interfaces.RealInput rate_in if use_rate_in
    "Rate in the declared unit (particles/s, or kg/s when rateKgPerSecond >= 0), >= 0"
    annotation (Placement(transformation(extent = {{-140, 40}, {-100, 80}})));
  Modelica.Blocks.Interfaces.BooleanInput on_in if use_on_in "true: inserting, false: paused"
    annotation (Placement(transformation(extent = {{-140, -80}, {-100, -40}})));
  Modelica.Blocks.Interfaces.IntegerOutput countTotal(start = 0, fixed = true) "Particles inserted since the start"
    annotation (Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Modelica.Blocks.Interfaces.RealOutput massTotal(unit = "kg", start = 0, fixed = true) "Mass inserted since the start"
    annotation (Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Modelica.Blocks.Interfaces.IntegerOutput shortfallTotal(start = 0, fixed = true)
    "Requested but not placed since the start (no room in the box)" annotation (Placement(transformation(extent = {{100, -30}, {120, -10}})));
  Modelica.Blocks.Interfaces.RealOutput massInterval(unit = "kg", start = 0, fixed = true) "Mass inserted in the last interval"
    annotation (Placement(transformation(extent = {{100, -70}, {120, -50}})));
protected
  parameter Real declaredRate = if rateKgPerSecond >= 0 then rateKgPerSecond else ratePerSecond
    "The declared rate in its unit (1/s or kg/s)" annotation (__DEMLink(mixedUnits = true));
  Modelica.Blocks.Interfaces.RealInput rateNow "rate_in, or the declared rate";
  Modelica.Blocks.Interfaces.BooleanInput onNow "on_in, or true";
  Real sentRate(start = declaredRate, fixed = true) "The rate the server inserts at";
  Boolean sentOn(start = true, fixed = true) "Whether the server inserts";
  Integer status(start = 0, fixed = true);
  Integer samplesSent(start = 0, fixed = true) "Samples whose inputs were sent (each sample's first call)";
  Integer samplesReceived(start = 0, fixed = true) "Samples whose outputs were received (the second call)";
  Integer counts[3](each start = 0, each fixed = true);
  Real masses[3](each start = 0, each fixed = true);
equation
  connect(rate_in, rateNow);
  if not use_rate_in then
    rateNow = declaredRate;
  end if;
  connect(on_in, onNow);
  if not use_on_in then
    onNow = true;
  end if;
algorithm
  when sample(0, tc) then
    // Run-time inputs when they changed: one-shot, sent with this sample's package and
    // applied from its step on (the read below sends it).
    if use_on_in and onNow <> sentOn then
      DEMLink.Functions.check(client, DEMLink.Functions.External.particleSourceSetEnabled(client, 0,
        if onNow then 1 else 0));
      sentOn := onNow;
    end if;
    if use_rate_in and DEMLink.Functions.changed({rateNow}, {sentRate}) then
      DEMLink.Functions.check(client, DEMLink.Functions.External.particleSourceSetRate(client, 0, rateNow));
      sentRate := rateNow;
    end if;
    // The sample's first call sends the inputs at t (send first; docs/modelica.md, "How a component runs").
    (status, counts, masses) := DEMLink.Functions.External.particleSourceRead(client, 0);
    DEMLink.Functions.checkExchange(client, status);
    samplesSent := pre(samplesSent) + 1;
  end when;
  when pre(samplesSent) > pre(samplesReceived) then
    // The event iteration after every component's first call: this one returns [t, t + tc].
    (status, counts, masses) := DEMLink.Functions.External.particleSourceRead(client, 0);
    DEMLink.Functions.checkExchange(client, status);
    samplesReceived := pre(samplesSent);
    countTotal := counts[2];
    massTotal := masses[2];
    shortfallTotal := counts[3];
    massInterval := masses[1];
  end when;
  annotation (Documentation(info = "<html><p>A box or disc region (docs/sources.md) with one of
the schema's radius distributions: one radius, uniform, linear pdf, truncated normal or
discrete (the solver paper's distributions). Declared through the generic layout of the C ABI
(docs/c_abi.md, particle_source).</p>
<p>Run-time inputs (as MSL sources do with <code>use_..._in</code>): with
<code>use_rate_in</code> the rate follows <code>rate_in</code> (in the declared unit), with
<code>use_on_in</code> insertion pauses while <code>on_in</code> is false. A change is sent
at the next sample and applies from that sample's DEM step on; the request accumulated so
far is kept, so switching on gives no burst. The start and stop times still apply.</p></html>"));
end ParticleSource;
