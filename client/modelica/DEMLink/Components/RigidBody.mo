within DEMLink.Components;
model RigidBody "A body (STL mesh on the server) moved by the system model; returns the particles' wrench"
  outer DEMLink.Basics.SimulationBox simBox;
  parameter String name = "body" "Unique component name";
  parameter String stlFile = "body.stl" "STL file on the SERVER";
  parameter String material = "steel" "Material name";
  parameter Real referencePoint[3] = {0, 0, 0} "Reference point in the STL frame [m]";
  parameter Real initialPose[7] = {0, 0, 0, 1, 0, 0, 0} "Initial position [m] and quaternion w x y z";
  parameter Integer motion = 1 "1: PREDICTED, 2: LAGGED (docs/protocol.md)";
  parameter Modelica.Units.SI.Time tc = simBox.tc "Communication interval";
  input Real position[3] "Reference point, world frame [m]";
  input Real orientation[4] "Quaternion w x y z, body -> world";
  input Real velocity[3] "Reference point velocity [m/s]";
  input Real angularVelocity[3] "World frame [rad/s]";
  output Real meanForce[3](each start = 0, each fixed = true) "On the body by the particles, interval mean [N]";
  output Real meanTorque[3](each start = 0, each fixed = true) "About the reference point, interval mean [N.m]";
  output Real force[3](each start = 0, each fixed = true) "At the end of the interval [N]";
  output Real torque[3](each start = 0, each fixed = true) "At the end of the interval [N.m]";
protected
  DEMLink.Functions.Client client = DEMLink.Functions.Client();
  parameter Integer handle(fixed = false);
  Integer status(start = 0, fixed = true);
  Real wrench[12](each start = 0, each fixed = true);
initial algorithm
  DEMLink.Functions.check(client, DEMLink.Functions.connectToHost(client, simBox.address, simBox.port, name, simBox.token));
  handle := DEMLink.Functions.declareRigidBodyStl(client, name, tc, stlFile, material, referencePoint,
    initialPose, motion);
algorithm
  when sample(0, tc) then
    (status, wrench) := DEMLink.Functions.rigidBodyExchange(client, handle, cat(1, position, orientation),
      cat(1, velocity, angularVelocity));
    DEMLink.Functions.check(client, status);
    meanForce := wrench[1:3];
    meanTorque := wrench[4:6];
    force := wrench[7:9];
    torque := wrench[10:12];
  end when;
  when terminal() then
    DEMLink.Functions.check(client, DEMLink.Functions.finish(client, "terminal()"));
  end when;
end RigidBody;
