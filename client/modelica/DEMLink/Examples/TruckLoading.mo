within DEMLink.Examples;
model TruckLoading "A truck bed on a sprung MultiBody axis (CADPartFrame) loaded by a ParticleSource; a sensor weighs the load"
  extends Modelica.Icons.Example;
  inner Modelica.Mechanics.MultiBody.World world(n = {0, 0, -1}, g = 9.81)
    annotation (Placement(transformation(extent = {{-90, -50}, {-70, -30}})));
  inner DEMLink.Basics.SimulationBox simBox(tc = 2e-3, timeout = 120, boundsLower = {-0.4, -0.3, -0.2},
    boundsUpper = {0.4, 0.3, 0.6}) annotation (Placement(transformation(extent = {{-90, 60}, {-70, 80}})));
  DEMLink.Components.Material gravel(name = "gravel", databaseName = "gravel")
    annotation (Placement(transformation(extent = {{-60, 60}, {-40, 80}})));
  DEMLink.Components.Plane ground(name = "ground", point = {0, 0, -0.1}, normal = {0, 0, 1}, material = "gravel")
    "Catches spilled particles; no feedback to the system model" annotation (Placement(transformation(extent = {{-30, 60}, {-10, 80}})));
  DEMLink.Components.ParticleSource source(name = "source", material = "gravel", centre = {0, 0, 0.3},
    halfExtents = {0.06, 0.04, 0.03}, rMin = 0.008, rMax = 0.01, ratePerSecond = -1, rateKgPerSecond = 4,
    velocity = {0, 0, -1}, startTime = 0, stopTime = 0.3, seed = 2) annotation (Placement(transformation(extent = {{0, 60}, {20, 80}})));
  DEMLink.Components.CADPartFrame truck(name = "truck", fileName = "modelica://DEMLink/Resources/Data/truck_bed.stl",
    material = "gravel") "The dump body; frame_a at its floor's centre" annotation (Placement(transformation(extent = {{40, -50}, {60, -30}})));
  DEMLink.Sensors.RegionSensor load(name = "load", attachedTo = "truck", centre = {0, 0, 0.1}, size = {0.3, 0.2, 0.2})
    "The bed's volume, moving with the truck" annotation (Placement(transformation(extent = {{30, 60}, {50, 80}})));
  parameter Modelica.Units.SI.Mass m = 50 "Sprung mass of the truck bed";
  parameter Modelica.Units.SI.TranslationalSpringConstant c = 5e4 "Suspension stiffness";
  parameter Modelica.Units.SI.TranslationalDampingConstant d = 2000 "Suspension damping";
  Modelica.Mechanics.MultiBody.Joints.Prismatic travel(n = {0, 0, 1}, useAxisFlange = true, s(start = 0, fixed = true),
    v(start = 0, fixed = true)) "Vertical travel of the bed" annotation (Placement(transformation(extent = {{-50, -50}, {-30, -30}})));
  Modelica.Mechanics.MultiBody.Parts.Body body(m = m, r_CM = {0, 0, 0}, animation = false)
    annotation (Placement(transformation(extent = {{0, -90}, {20, -70}})));
  Modelica.Mechanics.Translational.Components.SpringDamper suspension(c = c, d = d, s_rel0 = m * world.g / c)
    "Preloaded: the empty bed rests at s = 0" annotation (Placement(transformation(extent = {{-50, -20}, {-30, 0}})));
equation
  connect(world.frame_b, travel.frame_a) annotation (Line(points = {{-70, -40}, {-50, -40}}));
  connect(travel.frame_b, truck.frame_a) annotation (Line(points = {{-30, -40}, {40, -40}}));
  connect(travel.frame_b, body.frame_a) annotation (Line(points = {{-30, -40}, {-10, -40}, {-10, -80}, {0, -80}}));
  connect(suspension.flange_a, travel.support) annotation (Line(points = {{-50, -10}, {-50, -30}, {-44, -30}}));
  connect(suspension.flange_b, travel.axis) annotation (Line(points = {{-30, -10}, {-30, -30}, {-32, -30}}));
  annotation (experiment(StopTime = 0.8, Interval = 0.002), Documentation(info = "<html>
<p>The loaded-truck use case of the coupling paper (section 6.2), reduced to the dump body:
a 300 x 200 x 100 mm open box (CADPartFrame, STL sent from Resources/Data) on a vertical
prismatic joint with a preloaded spring-damper suspension. A ParticleSource pours gravel
at 4 kg/s for 0.3 s; the RegionSensor attached to the bed weighs the load; the particles'
wrench acts on the MultiBody frame, so the bed settles by the load's weight over the
stiffness. Start <code>demlink-server --port 47000</code> first.
tests/modelica/truck_loading_sequence.c makes this model's calls against a real server:
the load equals the delivered mass, and the bed's deflection matches the load.</p></html>"));
end TruckLoading;
