within DEMLink.Sensors;
model RegionSensor "Count, mass, centre of mass and mean velocity of the particles in a box or sphere"
  extends DEMLink.Interfaces.PartialComponent(name = "sensor", final kind = "region_sensor", final exchanged = true,
    final declInts = {Integer(shape) - 1}, final declReals = cat(1, centre,
    if shape == DEMLink.Types.RegionShape.Box then size else {radius, 0, 0}, orientation), final declStrings = {attachedTo});
  parameter DEMLink.Types.RegionShape shape = DEMLink.Types.RegionShape.Box "Region shape";
  parameter Modelica.Units.SI.Position centre[3] = {0, 0, 0} "Centre (body frame when attached)";
  parameter Modelica.Units.SI.Length size[3] = {1, 1, 1} "Box edge lengths" annotation (Dialog(enable = shape == DEMLink.Types.RegionShape.Box));
  parameter Real orientation[4] = {1, 0, 0, 0} "Box orientation, quaternion w x y z" annotation (Dialog(enable = shape == DEMLink.Types.RegionShape.Box));
  parameter Modelica.Units.SI.Radius radius = 0.5 "Sphere radius" annotation (Dialog(enable = shape == DEMLink.Types.RegionShape.Sphere));
  parameter String attachedTo = "" "Rigid body the region follows, e.g. a bucket (empty: fixed)";
  Modelica.Blocks.Interfaces.IntegerOutput count(start = 0, fixed = true) "Particles inside"
    annotation (Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Modelica.Blocks.Interfaces.RealOutput mass(unit = "kg", start = 0, fixed = true) "Their mass"
    annotation (Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Modelica.Blocks.Interfaces.RealOutput centreOfMass[3](each unit = "m", each start = 0, each fixed = true)
    "Their centre of mass (NaN when empty)" annotation (Placement(transformation(extent = {{100, -30}, {120, -10}})));
  Modelica.Blocks.Interfaces.RealOutput meanVelocity[3](each unit = "m/s", each start = 0, each fixed = true)
    "Their mean velocity (NaN when empty)" annotation (Placement(transformation(extent = {{100, -70}, {120, -50}})));
protected
  Integer status(start = 0, fixed = true);
  Real out[7](each start = 0, each fixed = true);
algorithm
  when sample(0, tc) then
    (status, count, out) := DEMLink.Functions.External.regionSensorRead(client, 0);
    DEMLink.Functions.checkExchange(client, status);
    mass := out[1];
    centreOfMass := out[2:4];
    meanVelocity := out[5:7];
  end when;
  annotation (Documentation(info = "<html><p>The coupling paper's RegionSensor (section 5.2),
e.g. the fill of an excavator's bucket when attached to it.</p></html>"));
end RegionSensor;
