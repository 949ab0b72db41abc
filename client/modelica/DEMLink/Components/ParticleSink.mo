within DEMLink.Components;
model ParticleSink "Removes the particles that enter a box or sphere"
  extends DEMLink.Interfaces.PartialComponent(name = "sink", final kind = "particle_sink", final exchanged = true,
    final declInts = {Integer(shape) - 1}, final declReals = cat(1, centre,
    if shape == DEMLink.Types.RegionShape.Box then size else {radius, 0, 0}, orientation), final declStrings = {attachedTo});
  parameter DEMLink.Types.RegionShape shape = DEMLink.Types.RegionShape.Box "Region shape";
  parameter Modelica.Units.SI.Position centre[3] = {0, 0, 0} "Centre (body frame when attached)";
  parameter Modelica.Units.SI.Length size[3] = {1, 1, 1} "Box edge lengths" annotation (Dialog(enable = shape == DEMLink.Types.RegionShape.Box));
  parameter Real orientation[4] = {1, 0, 0, 0} "Box orientation, quaternion w x y z" annotation (Dialog(enable = shape == DEMLink.Types.RegionShape.Box));
  parameter Modelica.Units.SI.Radius radius = 0.5 "Sphere radius" annotation (Dialog(enable = shape == DEMLink.Types.RegionShape.Sphere));
  parameter String attachedTo = "" "Rigid body the region follows (empty: fixed)";
  Modelica.Blocks.Interfaces.IntegerOutput countTotal(start = 0, fixed = true) "Particles removed since the start"
    annotation (Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Modelica.Blocks.Interfaces.RealOutput massTotal(unit = "kg", start = 0, fixed = true) "Mass removed since the start"
    annotation (Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Modelica.Blocks.Interfaces.RealOutput massInterval(unit = "kg", start = 0, fixed = true) "Mass removed in the last interval"
    annotation (Placement(transformation(extent = {{100, -30}, {120, -10}})));
protected
  Integer status(start = 0, fixed = true);
  Integer counts[2](each start = 0, each fixed = true);
  Real masses[2](each start = 0, each fixed = true);
algorithm
  when sample(0, tc) then
    (status, counts, masses) := DEMLink.Functions.External.particleSinkRead(client, 0);
    DEMLink.Functions.checkExchange(client, status);
    countTotal := counts[2];
    massTotal := masses[2];
    massInterval := masses[1];
  end when;
end ParticleSink;
