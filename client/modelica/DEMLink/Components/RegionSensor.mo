within DEMLink.Components;
model RegionSensor "Count, mass, centre of mass and mean velocity of the particles in a box"
  outer DEMLink.Basics.SimulationBox simBox;
  parameter String name = "sensor" "Unique component name";
  parameter Real centre[3] = {0, 0, 0} "Box centre (in the body frame when attached) [m]";
  parameter Real size[3] = {1, 1, 1} "Box edge lengths [m]";
  parameter String attachedTo = "" "RigidBody name the box follows; empty: fixed";
  parameter Modelica.Units.SI.Time tc = simBox.tc "Communication interval";
  output Integer count(start = 0, fixed = true) "Particles inside";
  output Real mass(start = 0, fixed = true) "[kg]";
  output Real centreOfMass[3](each start = 0, each fixed = true) "[m]";
  output Real meanVelocity[3](each start = 0, each fixed = true) "[m/s]";
protected
  DEMLink.Functions.Client client = DEMLink.Functions.Client();
  parameter Integer handle(fixed = false);
  Integer status(start = 0, fixed = true);
  Real out[7](each start = 0, each fixed = true);
initial algorithm
  DEMLink.Functions.check(client, DEMLink.Functions.connectToHost(client, simBox.address, simBox.port, name, simBox.token));
  handle := DEMLink.Functions.declareRegionSensorBox(client, name, tc, centre, size, attachedTo);
algorithm
  when sample(0, tc) then
    (status, count, out) := DEMLink.Functions.regionSensorRead(client, handle);
    DEMLink.Functions.check(client, status);
    mass := out[1];
    centreOfMass := out[2:4];
    meanVelocity := out[5:7];
  end when;
  when terminal() then
    DEMLink.Functions.check(client, DEMLink.Functions.finish(client, "terminal()"));
  end when;
end RegionSensor;
