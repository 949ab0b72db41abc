within DEMLink.Interfaces;
partial model PartialDeformableBody "Connection, driven pose, reactions and Bye of a deformable body (mass-spring or FEM)"
  outer DEMLink.Basics.SimulationBox simBox "The model's inner SimulationBox";
  parameter String name "Unique component name on the server";
  parameter Modelica.Units.SI.Time tc = simBox.tc "Communication interval";
  parameter String material = "steel" "Contact material of the body's surface";
  parameter Real fixedRegions[:](each unit = "m") = fill(0.0, 0)
    "Boxes whose nodes are fixed: lo x y z, hi x y z per box [m] (6 values each)";
  parameter Real drivenRegions[:](each unit = "m") = fill(0.0, 0)
    "Boxes whose nodes follow the driven pose: lo x y z, hi x y z per box [m] (6 values each)";
  parameter Modelica.Units.SI.Position drivenReference[3] = {0, 0, 0} "Point the driven pose refers to, at t = 0";
  parameter String attachedTo = "" "Rigid body whose pose drives the driven nodes (empty: the inputs do)";
  parameter Boolean useDrivenPose = false "Drive the driven nodes from the inputs position/orientation/velocity/angularVelocity";
  Modelica.Blocks.Interfaces.RealInput position[3](each unit = "m") if useDrivenPose "Driving reference point, world frame"
    annotation (Placement(transformation(extent = {{-140, 40}, {-100, 80}})));
  Modelica.Blocks.Interfaces.RealInput orientation[4] if useDrivenPose "Rotation from the initial configuration, w x y z"
    annotation (Placement(transformation(extent = {{-140, 0}, {-100, 40}})));
  Modelica.Blocks.Interfaces.RealInput velocity[3](each unit = "m/s") if useDrivenPose "Reference point velocity"
    annotation (Placement(transformation(extent = {{-140, -40}, {-100, 0}})));
  Modelica.Blocks.Interfaces.RealInput angularVelocity[3](each unit = "rad/s") if useDrivenPose "World frame"
    annotation (Placement(transformation(extent = {{-140, -80}, {-100, -40}})));
  Modelica.Blocks.Interfaces.RealOutput drivenForce[3](each unit = "N", each start = 0, each fixed = true)
    "Reaction of the driven nodes ON the body" annotation (Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Modelica.Blocks.Interfaces.RealOutput drivenTorque[3](each unit = "N.m", each start = 0, each fixed = true)
    "About the driving position" annotation (Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Modelica.Blocks.Interfaces.RealOutput fixedForce[3](each unit = "N", each start = 0, each fixed = true)
    "Reaction of the fixed nodes ON the body" annotation (Placement(transformation(extent = {{100, -30}, {120, -10}})));
  Modelica.Blocks.Interfaces.RealOutput fixedTorque[3](each unit = "N.m", each start = 0, each fixed = true)
    "About the world origin" annotation (Placement(transformation(extent = {{100, -70}, {120, -50}})));
  Modelica.Blocks.Interfaces.IntegerOutput brokenSprings(start = 0, fixed = true) "Springs broken so far (0 for FEM)";
protected
  DEMLink.Functions.Client client = DEMLink.Functions.Client(simBox.address, simBox.port, name, simBox.token,
    simBox.timeout) "This body's connection, connected by its constructor";
  parameter Integer handle(fixed = false) "The body's handle on its connection (set by the declaration)";
  parameter Integer declareStatus(fixed = false) "dl_status of the declaration";
  Integer status(start = 0, fixed = true);
  Integer samplesSent(start = 0, fixed = true) "Samples whose inputs were sent (each sample's first call)";
  Integer samplesReceived(start = 0, fixed = true) "Samples whose outputs were received (the second call)";
  Real reactions[12](each start = 0, each fixed = true);
  Modelica.Blocks.Interfaces.RealInput poseNow[13] "The driven pose and twist inputs, or the initial pose";
equation
  connect(position, poseNow[1:3]);
  connect(orientation, poseNow[4:7]);
  connect(velocity, poseNow[8:10]);
  connect(angularVelocity, poseNow[11:13]);
  if not useDrivenPose then
    poseNow = cat(1, drivenReference, {1, 0, 0, 0}, zeros(6));
  end if;
algorithm
  when sample(0, tc) then
    // The sample's first call sends the inputs at t (send first; docs/modelica.md, "How a component runs").
    (status, reactions, brokenSprings) := DEMLink.Functions.External.deformableBodyExchange(client, handle,
      if useDrivenPose then 1 else 0, poseNow[1:7], poseNow[8:13]);
    DEMLink.Functions.checkExchange(client, status);
    samplesSent := pre(samplesSent) + 1;
  end when;
  when pre(samplesSent) > pre(samplesReceived) then
    // The event iteration after every component's first call: this one returns [t, t + tc].
    (status, reactions, brokenSprings) := DEMLink.Functions.External.deformableBodyExchange(client, handle,
      if useDrivenPose then 1 else 0, poseNow[1:7], poseNow[8:13]);
    DEMLink.Functions.checkExchange(client, status);
    samplesReceived := pre(samplesSent);
    drivenForce := reactions[1:3];
    drivenTorque := reactions[4:6];
    fixedForce := reactions[7:9];
    fixedTorque := reactions[10:12];
  end when;
  when terminal() then
    DEMLink.Functions.finish(client);
  end when;
  annotation (Icon(graphics = {Rectangle(extent = {{-100, 100}, {100, -100}}, lineColor = {95, 75, 45},
    fillColor = {220, 230, 245}, fillPattern = FillPattern.Solid), Text(extent = {{-150, 140}, {150, 105}},
    textString = "%name", textColor = {0, 0, 255})}), Documentation(info = "<html>
<p>A deformable body (docs/deformable.md) on its own connection: the subclass declares it
with the C ABI's typed call in its initial algorithm; at every <code>sample(0, tc)</code> the
body sends the driven pose (with <code>useDrivenPose</code>) and, in the event iteration
after every component has sent, reads the reactions of the interval that begins there.</p></html>"));
end PartialDeformableBody;
