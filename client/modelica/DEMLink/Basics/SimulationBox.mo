within DEMLink.Basics;
model SimulationBox "Server address, communication interval and scene-wide settings (use as inner simBox)"
  parameter String address = "127.0.0.1" "Host of demlink-server";
  parameter Integer port = 47000 "TCP port of demlink-server (its --port)";
  parameter String token = "" "Access token when the server requires one";
  parameter Modelica.Units.SI.Time tc = 1e-3 "Communication interval of the components";
  parameter Modelica.Units.SI.Time timeStep = 1e-5 "DEM time step";
  parameter Real restitutionTolerance = 0.01
    "Largest restitution error the server's time-step limit allows; larger accepts a larger timeStep (trades accuracy for speed)";
  parameter Modelica.Units.SI.Time endTime = 10 "Simulated time of the DEM run";
  parameter Real gravity[3] = {0, 0, -9.81} "Gravity [m/s2]";
  parameter Real boundsLower[3] = {-5, -5, -5} "Lower corner of the DEM domain [m]";
  parameter Real boundsUpper[3] = {5, 5, 5} "Upper corner of the DEM domain [m]";
  parameter Integer nComponents = 1 "Components in the model, this box included (the server compiles once all are declared)";
  parameter Real timeout = 30 "Longest wait for the server in one call [s]";
  output Integer particleCount(start = 0, fixed = true) "Particles in the DEM world";
  output Real totalMass(start = 0, fixed = true) "Mass of all particles [kg]";
  output Real kineticEnergy(start = 0, fixed = true) "Kinetic energy of all particles [J]";
protected
  DEMLink.Functions.Client client = DEMLink.Functions.Client();
  parameter Integer handle(fixed = false);
  Integer status(start = 0, fixed = true);
  Real out[4](each start = 0, each fixed = true);
initial algorithm
  DEMLink.Functions.check(client, DEMLink.Functions.setTimeout(client, timeout));
  DEMLink.Functions.check(client, DEMLink.Functions.connectToHost(client, address, port, "simBox", token));
  handle := DEMLink.Functions.declareSimulationBox(client, "simBox", tc, timeStep, endTime, gravity,
    boundsLower, boundsUpper, nComponents, restitutionTolerance);
algorithm
  when sample(0, tc) then
    (status, out, particleCount) := DEMLink.Functions.simulationBoxExchange(client, handle, gravity);
    DEMLink.Functions.check(client, status);
    totalMass := out[2];
    kineticEnergy := out[3];
  end when;
  when terminal() then
    DEMLink.Functions.check(client, DEMLink.Functions.finish(client, "terminal()"));
  end when;
  annotation (defaultComponentName = "simBox", defaultComponentPrefixes = "inner",
    missingInnerMessage = "Add an inner DEMLink.Basics.SimulationBox simBox to the model.");
end SimulationBox;
