within DEMLink.Sensors;
model RegionSensor "Count, mass, centre of mass and mean velocity of the particles in a box or sphere"
  extends DEMLink.Interfaces.PartialComponent(name = "sensor", final kind = "region_sensor", final exchanged = true,
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
  parameter String attachedTo = "" "Rigid body the region follows, e.g. a bucket (empty: fixed)";
  parameter Boolean use_pose_in = false "Centre and orientation from the inputs centre_in, orientation_in"
    annotation (Evaluate = true, choices(checkBox = true), Dialog(group = "Run-time inputs"));
  parameter Boolean use_size_in = false "Box size from size_in, or sphere radius from radius_in"
    annotation (Evaluate = true, choices(checkBox = true), Dialog(group = "Run-time inputs"));
  Modelica.Blocks.Interfaces.RealInput centre_in[3](each unit = "m") if use_pose_in
    "Centre (body frame when attached)" annotation (Placement(transformation(extent = {{-140, 40}, {-100, 80}})));
  Modelica.Blocks.Interfaces.RealInput orientation_in[4] if use_pose_in "Orientation, quaternion w x y z"
    annotation (Placement(transformation(extent = {{-140, 0}, {-100, 40}})));
  Modelica.Blocks.Interfaces.RealInput size_in[3](each unit = "m") if use_size_in and shape == DEMLink.Types.RegionShape.Box
    "Box edge lengths" annotation (Placement(transformation(extent = {{-140, -40}, {-100, 0}})));
  Modelica.Blocks.Interfaces.RealInput radius_in(unit = "m") if use_size_in and shape == DEMLink.Types.RegionShape.Sphere
    "Sphere radius" annotation (Placement(transformation(extent = {{-140, -80}, {-100, -40}})));
  Modelica.Blocks.Interfaces.IntegerOutput count(start = 0, fixed = true) "Particles inside"
    annotation (Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Modelica.Blocks.Interfaces.RealOutput mass(unit = "kg", start = 0, fixed = true) "Their mass"
    annotation (Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Modelica.Blocks.Interfaces.RealOutput centreOfMass[3](each unit = "m", each start = 0, each fixed = true)
    "Their centre of mass (0 when empty)" annotation (Placement(transformation(extent = {{100, -30}, {120, -10}})));
  Modelica.Blocks.Interfaces.RealOutput meanVelocity[3](each unit = "m/s", each start = 0, each fixed = true)
    "Their mean velocity (0 when empty)" annotation (Placement(transformation(extent = {{100, -70}, {120, -50}})));
  Modelica.Blocks.Interfaces.IntegerOutput bondsIntact(start = 0, fixed = true)
    "Intact parallel bonds whose midpoint is inside" annotation (Placement(transformation(extent = {{100, -100}, {120, -80}})));
  Modelica.Blocks.Interfaces.IntegerOutput bondsBroken(start = 0, fixed = true)
    "Broken parallel bonds whose midpoint is inside" annotation (Placement(transformation(extent = {{100, 80}, {120, 100}})));
protected
  Modelica.Blocks.Interfaces.RealInput centreNow[3] "centre_in, or centre";
  Modelica.Blocks.Interfaces.RealInput orientationNow[4] "orientation_in, or orientation";
  Modelica.Blocks.Interfaces.RealInput sizeNow[3] "size_in, or size";
  Modelica.Blocks.Interfaces.RealInput radiusNow "radius_in, or radius";
  Real sentPose[7](start = cat(1, centre, orientation), each fixed = true) "The pose the server uses";
  Real sentSize[4](start = cat(1, size, {radius}), each fixed = true) "The size and radius the server uses";
  Integer status(start = 0, fixed = true);
  Integer samplesSent(start = 0, fixed = true) "Samples whose inputs were sent (each sample's first call)";
  Integer samplesReceived(start = 0, fixed = true) "Samples whose outputs were received (the second call)";
  Real out[7](each start = 0, each fixed = true);
  Integer bonds[2](each start = 0, each fixed = true) "Intact, broken";
equation
  connect(centre_in, centreNow);
  connect(orientation_in, orientationNow);
  if not use_pose_in then
    centreNow = centre;
    orientationNow = orientation;
  end if;
  connect(size_in, sizeNow);
  if not (use_size_in and shape == DEMLink.Types.RegionShape.Box) then
    sizeNow = size;
  end if;
  connect(radius_in, radiusNow);
  if not (use_size_in and shape == DEMLink.Types.RegionShape.Sphere) then
    radiusNow = radius;
  end if;
algorithm
  when sample(0, tc) then
    // Pose or extent changed: one-shot, sent with this sample's package (the read below),
    // applied from its step on.
    if use_pose_in and DEMLink.Functions.changed(cat(1, centreNow, orientationNow), sentPose) or
       use_size_in and DEMLink.Functions.changed(cat(1, sizeNow, {radiusNow}), sentSize) then
      DEMLink.Functions.check(client, DEMLink.Functions.External.regionSensorSetRegion(client, 0,
        if use_pose_in then 1 else 0, centreNow, orientationNow, if use_size_in then 1 else 0,
        if shape == DEMLink.Types.RegionShape.Sphere then 1 else 0, sizeNow, radiusNow));
      sentPose := cat(1, centreNow, orientationNow);
      sentSize := cat(1, sizeNow, {radiusNow});
    end if;
    // The sample's first call sends the inputs at t (send first; docs/modelica.md, "How a component runs").
    (status, count, out, bonds) := DEMLink.Functions.External.regionSensorReadBonds(client, 0);
    DEMLink.Functions.checkExchange(client, status);
    samplesSent := pre(samplesSent) + 1;
  end when;
  when pre(samplesSent) > pre(samplesReceived) then
    // The event iteration after every component's first call: this one returns [t, t + tc].
    (status, count, out, bonds) := DEMLink.Functions.External.regionSensorReadBonds(client, 0);
    DEMLink.Functions.checkExchange(client, status);
    samplesReceived := pre(samplesSent);
    mass := out[1];
    centreOfMass := out[2:4];
    meanVelocity := out[5:7];
    bondsIntact := bonds[1];
    bondsBroken := bonds[2];
  end when;
  annotation (Documentation(info = "<html><p>The coupling paper's RegionSensor (section 5.2),
e.g. the fill of an excavator's bucket when attached to it. <code>bondsIntact</code> and
<code>bondsBroken</code> count the parallel bonds (ParallelBonds) whose midpoint is inside.</p>
<p>Run-time inputs: with <code>use_pose_in</code> the region follows <code>centre_in</code>
and <code>orientation_in</code>, with <code>use_size_in</code> its edge lengths
(<code>size_in</code>, box) or radius (<code>radius_in</code>, sphere); in the frame it was
declared in (world, or the attached body's). A change is sent at the next sample and applies
from that sample's DEM step on.</p></html>"));
end RegionSensor;
