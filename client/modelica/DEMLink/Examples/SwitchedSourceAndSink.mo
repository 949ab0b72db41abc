within DEMLink.Examples;
model SwitchedSourceAndSink "Run-time inputs: a source's rate stepped and switched off, a sink switched on, a sensor moved onto the pile"
  extends Modelica.Icons.Example;
  inner DEMLink.Basics.SimulationBox simBox(tc = 2e-3, timeout = 120, boundsLower = {-0.5, -0.4, -0.1},
    boundsUpper = {0.5, 0.4, 0.6}) annotation (Placement(transformation(extent = {{-90, 60}, {-70, 80}})));
  DEMLink.Components.Material gravel(name = "gravel", databaseName = "gravel")
    annotation (Placement(transformation(extent = {{-60, 60}, {-40, 80}})));
  DEMLink.Components.Plane ground(name = "ground", point = {0, 0, 0}, normal = {0, 0, 1}, material = "gravel")
    annotation (Placement(transformation(extent = {{-30, 60}, {-10, 80}})));
  DEMLink.Components.ParticleSource source(name = "source", material = "gravel", centre = {0, 0, 0.3},
    halfExtents = {0.1, 0.06, 0.04}, rMin = 0.008, rMax = 0.01, ratePerSecond = -1, rateKgPerSecond = 4,
    velocity = {0, 0, -1}, seed = 2, use_rate_in = true, use_on_in = true)
    "Pours gravel at rate_in [kg/s] while on_in" annotation (Placement(transformation(extent = {{10, 20}, {30, 40}})));
  DEMLink.Components.ParticleSink sink(name = "sink", centre = {0, 0, 0.1}, size = {0.8, 0.6, 0.2}, use_on_in = true)
    "The floor's volume: removes the pile once switched on" annotation (Placement(transformation(extent = {{10, -20}, {30, 0}})));
  DEMLink.Sensors.RegionSensor pile(name = "pile", centre = {0, 0, 0.45}, size = {0.1, 0.1, 0.1}, use_pose_in = true,
    use_size_in = true) "Declared small and above the source; the inputs make it the floor's volume at 0.5 s"
    annotation (Placement(transformation(extent = {{10, -60}, {30, -40}})));
  Modelica.Blocks.Sources.Step rate(offset = 4, height = 4, startTime = 0.099) "4 kg/s, 8 kg/s from the sample at 0.1 s"
    annotation (Placement(transformation(extent = {{-60, 30}, {-40, 50}})));
  Modelica.Blocks.Sources.BooleanStep gate(startTime = 0.199, startValue = true) "Source on until the sample at 0.2 s"
    annotation (Placement(transformation(extent = {{-60, 0}, {-40, 20}})));
  Modelica.Blocks.Sources.BooleanStep sinkOn(startTime = 0.599, startValue = false) "Sink on from the sample at 0.6 s"
    annotation (Placement(transformation(extent = {{-60, -20}, {-40, 0}})));
  Modelica.Blocks.Sources.RealExpression pileCentre[3](y = {0, 0, if time < 0.499 then 0.45 else 0.1})
    "Onto the floor at the sample at 0.5 s" annotation (Placement(transformation(extent = {{-60, -50}, {-40, -30}})));
  Modelica.Blocks.Sources.Constant pileOrientation[4](k = {1, 0, 0, 0})
    annotation (Placement(transformation(extent = {{-60, -80}, {-40, -60}})));
  Modelica.Blocks.Sources.Constant pileSize[3](k = {0.8, 0.6, 0.2}) "The floor's volume, as the sink's"
    annotation (Placement(transformation(extent = {{-60, -110}, {-40, -90}})));
equation
  connect(rate.y, source.rate_in) annotation (Line(points = {{-39, 40}, {-20, 40}, {-20, 36}, {8, 36}}));
  connect(gate.y, source.on_in) annotation (Line(points = {{-39, 10}, {-20, 10}, {-20, 24}, {8, 24}}));
  connect(sinkOn.y, sink.on_in) annotation (Line(points = {{-39, -10}, {8, -10}}));
  connect(pileCentre.y, pile.centre_in) annotation (Line(points = {{-39, -40}, {-20, -40}, {-20, -44}, {8, -44}}));
  connect(pileOrientation.y, pile.orientation_in) annotation (Line(points = {{-39, -70}, {-16, -70}, {-16, -48}, {8, -48}}));
  connect(pileSize.y, pile.size_in) annotation (Line(points = {{-39, -100}, {-12, -100}, {-12, -52}, {8, -52}}));
  annotation (experiment(StopTime = 0.8, Interval = 0.002), Documentation(info = "<html>
<p>The run-time inputs of sources, sinks and sensors. The source pours gravel at 4 kg/s,
at 8 kg/s from 0.1 s, and is switched off at 0.2 s (1.2 kg in all). The sink covers the
floor but is off, so the pile stays, until it is switched on at 0.6 s. The sensor is
declared small and above the source; its inputs give it the floor's volume at once and
move it onto the floor at 0.5 s. Each input changes just before a sample so that it takes
effect at that sample's DEM step. Start <code>demlink-server --port 47000</code> first.
tests/modelica/switched_source_sequence.c makes this model's calls against a real server:
the delivered mass stops growing when the source is off, the pile stays while the sink is
off, and the sink then removes it.</p></html>"));
end SwitchedSourceAndSink;
