within DEMLink.Interfaces;
partial model PartialRigidBody "A body moved by the system model; returns the wrench of the particles on it"
  extends DEMLink.Interfaces.PartialComponent(final kind = "rigid_body", final exchanged = true,
    final declInts = {geometry, Integer(motion)}, final declReals = cat(1, referencePoint, initialPosition,
    initialOrientation, boxSize), final declStrings = {material, geometryText});
  parameter String material = "gravel" "Material name (a Material component or a database name)";
  parameter Modelica.Units.SI.Position referencePoint[3] = {0, 0, 0}
    "Reference point in the geometry's frame: the point whose pose is sent, and the torque's reference";
  parameter Modelica.Units.SI.Position initialPosition[3] = {0, 0, 0} "Reference point at the start, world frame";
  parameter Real initialOrientation[4](each unit = "1") = {1, 0, 0, 0} "Quaternion w x y z, body to world, at the start";
  parameter DEMLink.Types.BodyMotion motion = DEMLink.Types.BodyMotion.Predicted "Motion between exchanges";
  parameter Integer geometry "0: STL file on the server, 1: box, 2: STL file on the client";
  parameter String geometryText "STL path (geometry 0 or 2)";
  parameter Modelica.Units.SI.Length boxSize[3] = {0.1, 0.1, 0.1} "Edge lengths of the box (geometry 1)";
  Modelica.Blocks.Interfaces.RealOutput meanForce[3](each unit = "N", each start = 0, each fixed = true)
    "Force on the body by the particles, mean over the interval that began at the last sample, world frame"
    annotation (Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Modelica.Blocks.Interfaces.RealOutput meanTorque[3](each unit = "N.m", each start = 0, each fixed = true)
    "Torque about the reference point, interval mean, world frame"
    annotation (Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Modelica.Blocks.Interfaces.RealOutput force[3](each unit = "N", each start = 0, each fixed = true)
    "Force at the end of the interval, world frame" annotation (Placement(transformation(extent = {{100, -30}, {120, -10}})));
  Modelica.Blocks.Interfaces.RealOutput torque[3](each unit = "N.m", each start = 0, each fixed = true)
    "Torque at the end of the interval, world frame" annotation (Placement(transformation(extent = {{100, -70}, {120, -50}})));
protected
  Real pose[7] "Sent: reference point x y z [m], quaternion w x y z (body to world)";
  Real twist[6] "Sent: reference point velocity [m/s], angular velocity [rad/s], world frame";
  Integer status(start = 0, fixed = true);
  Integer samplesSent(start = 0, fixed = true) "Samples whose inputs were sent (each sample's first call)";
  Integer samplesReceived(start = 0, fixed = true) "Samples whose outputs were received (the second call)";
  Real wrench[12](each start = 0, each fixed = true);
algorithm
  when sample(0, tc) then
    // The sample's first call sends the inputs at t (send first; docs/modelica.md, "How a component runs").
    (status, wrench) := DEMLink.Functions.External.rigidBodyExchange(client, 0, pose, twist);
    DEMLink.Functions.checkExchange(client, status);
    samplesSent := pre(samplesSent) + 1;
  end when;
  when pre(samplesSent) > pre(samplesReceived) then
    // The event iteration after every component's first call: this one returns [t, t + tc].
    (status, wrench) := DEMLink.Functions.External.rigidBodyExchange(client, 0, pose, twist);
    DEMLink.Functions.checkExchange(client, status);
    samplesReceived := pre(samplesSent);
    meanForce := wrench[1:3];
    meanTorque := wrench[4:6];
    force := wrench[7:9];
    torque := wrench[10:12];
  end when;
end PartialRigidBody;
