within DEMLink.Components;
model ParticleSink "Removes the particles that enter a box or sphere"
  extends DEMLink.Interfaces.PartialComponent(name = "sink", final kind = "particle_sink", final exchanged = true,
    final declInts = {Integer(shape) - 1}, final declReals = cat(1, centre,
    if shape == DEMLink.Types.RegionShape.Box then size else {radius, 0, 0}, orientation, velocity),
    final declStrings = {attachedTo});
  parameter DEMLink.Types.RegionShape shape = DEMLink.Types.RegionShape.Box "Region shape";
  parameter Modelica.Units.SI.Position centre[3] = {0, 0, 0} "Centre (body frame when attached)";
  parameter Modelica.Units.SI.Length size[3] = {1, 1, 1} "Box edge lengths" annotation (Dialog(enable = shape == DEMLink.Types.RegionShape.Box));
  parameter Real orientation[4](each unit = "1") = {1, 0, 0, 0} "Box orientation, quaternion w x y z" annotation (Dialog(enable = shape == DEMLink.Types.RegionShape.Box));
  parameter Modelica.Units.SI.Radius radius = 0.5 "Sphere radius" annotation (Dialog(enable = shape == DEMLink.Types.RegionShape.Sphere));
  parameter Modelica.Units.SI.Velocity velocity[3] = {0, 0, 0}
    "Constant velocity of a region that is not attached (centre: where it is at t = 0)";
  parameter String attachedTo = "" "Rigid body the region follows (empty: fixed)";
  parameter Boolean use_on_in = false "Removal switched on and off by the input on_in"
    annotation (Evaluate = true, choices(checkBox = true), Dialog(group = "Run-time inputs"));
  Modelica.Blocks.Interfaces.BooleanInput on_in if use_on_in "true: removing, false: the particles stay"
    annotation (Placement(transformation(extent = {{-140, -20}, {-100, 20}})));
  Modelica.Blocks.Interfaces.IntegerOutput countTotal(start = 0, fixed = true) "Particles removed since the start"
    annotation (Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Modelica.Blocks.Interfaces.RealOutput massTotal(unit = "kg", start = 0, fixed = true) "Mass removed since the start"
    annotation (Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Modelica.Blocks.Interfaces.RealOutput massInterval(unit = "kg", start = 0, fixed = true) "Mass removed in the last interval"
    annotation (Placement(transformation(extent = {{100, -30}, {120, -10}})));
protected
  Modelica.Blocks.Interfaces.BooleanInput onNow "on_in, or true";
  Boolean sentOn(start = true, fixed = true) "Whether the server removes";
  Integer status(start = 0, fixed = true);
  Integer samplesSent(start = 0, fixed = true) "Samples whose inputs were sent (each sample's first call)";
  Integer samplesReceived(start = 0, fixed = true) "Samples whose outputs were received (the second call)";
  Integer counts[2](each start = 0, each fixed = true);
  Real masses[2](each start = 0, each fixed = true);
equation
  connect(on_in, onNow);
  if not use_on_in then
    onNow = true;
  end if;
algorithm
  when sample(0, tc) then
    // A change of on_in: one-shot, sent with this sample's package, applied from its step on.
    if use_on_in and onNow <> sentOn then
      DEMLink.Functions.check(client, DEMLink.Functions.External.particleSinkSetEnabled(client, 0,
        if onNow then 1 else 0));
      sentOn := onNow;
    end if;
    // The sample's first call sends the inputs at t (send first; docs/modelica.md, "How a component runs").
    (status, counts, masses) := DEMLink.Functions.External.particleSinkRead(client, 0);
    DEMLink.Functions.checkExchange(client, status);
    samplesSent := pre(samplesSent) + 1;
  end when;
  when pre(samplesSent) > pre(samplesReceived) then
    // The event iteration after every component's first call: this one returns [t, t + tc].
    (status, counts, masses) := DEMLink.Functions.External.particleSinkRead(client, 0);
    DEMLink.Functions.checkExchange(client, status);
    samplesReceived := pre(samplesSent);
    countTotal := counts[2];
    massTotal := masses[2];
    massInterval := masses[1];
  end when;
  annotation (Documentation(info = "<html><p>With <code>use_on_in</code> the sink removes
particles only while <code>on_in</code> is true (a gate or a hopper's outlet); a change is
sent at the next sample and applies from that sample's DEM step on.</p></html>"));
end ParticleSink;
