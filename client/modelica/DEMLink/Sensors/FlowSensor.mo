within DEMLink.Sensors;
model FlowSensor "Count and mass of the particles crossing a rectangle or disc"
  extends DEMLink.Interfaces.PartialComponent(name = "flow", final kind = "flow_sensor", final exchanged = true,
    final declInts = {Integer(shape) - 1}, final declReals = cat(1, centre, normal,
    if shape == DEMLink.Types.FlowShape.Rectangle then {length, width} else {radius, 0}, lengthAxis, velocity),
    final declStrings = {attachedTo});
  parameter DEMLink.Types.FlowShape shape = DEMLink.Types.FlowShape.Disc "Surface shape";
  parameter Modelica.Units.SI.Position centre[3] = {0, 0, 0} "Centre (body frame when attached)";
  parameter Real normal[3](each unit = "1") = {0, 0, 1} "Normal: crossings along it count as positive";
  parameter Modelica.Units.SI.Radius radius = 0.5 "Disc radius" annotation (Dialog(enable = shape == DEMLink.Types.FlowShape.Disc));
  parameter Modelica.Units.SI.Length length = 1 "Rectangle length" annotation (Dialog(enable = shape == DEMLink.Types.FlowShape.Rectangle));
  parameter Modelica.Units.SI.Length width = 1 "Rectangle width" annotation (Dialog(enable = shape == DEMLink.Types.FlowShape.Rectangle));
  parameter Real lengthAxis[3](each unit = "1") = {1, 0, 0} "Direction of the rectangle's length (perpendicular to normal)"
    annotation (Dialog(enable = shape == DEMLink.Types.FlowShape.Rectangle));
  parameter Modelica.Units.SI.Velocity velocity[3] = {0, 0, 0}
    "Constant velocity of a surface that is not attached (centre: where it is at t = 0)";
  parameter String attachedTo = "" "Rigid body the surface follows (empty: fixed)";
  Modelica.Blocks.Interfaces.IntegerOutput positiveCountTotal(start = 0, fixed = true) "Crossings along the normal since the start"
    annotation (Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Modelica.Blocks.Interfaces.IntegerOutput negativeCountTotal(start = 0, fixed = true) "Crossings against the normal since the start"
    annotation (Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Modelica.Blocks.Interfaces.RealOutput positiveMassTotal(unit = "kg", start = 0, fixed = true) "Mass along the normal since the start"
    annotation (Placement(transformation(extent = {{100, -30}, {120, -10}})));
  Modelica.Blocks.Interfaces.RealOutput negativeMassTotal(unit = "kg", start = 0, fixed = true) "Mass against the normal since the start"
    annotation (Placement(transformation(extent = {{100, -70}, {120, -50}})));
protected
  Integer status(start = 0, fixed = true);
  Integer samplesSent(start = 0, fixed = true) "Samples whose inputs were sent (each sample's first call)";
  Integer samplesReceived(start = 0, fixed = true) "Samples whose outputs were received (the second call)";
  Integer counts[4](each start = 0, each fixed = true);
  Real masses[4](each start = 0, each fixed = true);
algorithm
  when sample(0, tc) then
    // The sample's first call sends the inputs at t (send first; docs/modelica.md, "How a component runs").
    (status, counts, masses) := DEMLink.Functions.External.flowSensorRead(client, 0);
    DEMLink.Functions.checkExchange(client, status);
    samplesSent := pre(samplesSent) + 1;
  end when;
  when pre(samplesSent) > pre(samplesReceived) then
    // The event iteration after every component's first call: this one returns [t, t + tc].
    (status, counts, masses) := DEMLink.Functions.External.flowSensorRead(client, 0);
    DEMLink.Functions.checkExchange(client, status);
    samplesReceived := pre(samplesSent);
    positiveCountTotal := counts[3];
    negativeCountTotal := counts[4];
    positiveMassTotal := masses[3];
    negativeMassTotal := masses[4];
  end when;
end FlowSensor;
