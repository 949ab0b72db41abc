within DEMLink.Components;
model ParticleSource "Inserts particles into a box at a steady rate"
  outer DEMLink.Basics.SimulationBox simBox;
  parameter String name = "source" "Unique component name";
  parameter String material = "gravel" "Material name";
  parameter Real centre[3] = {0, 0, 1} "Box centre [m]";
  parameter Real halfExtents[3] = {0.2, 0.2, 0.1} "Half edge lengths [m]";
  parameter Real rMin = 0.01 "Smallest radius [m]";
  parameter Real rMax = 0.01 "Largest radius [m]";
  parameter Real ratePerSecond = 1000 "Particles per second (negative: use rateKgPerSecond)";
  parameter Real rateKgPerSecond = -1 "[kg/s] (negative: use ratePerSecond)";
  parameter Real velocity[3] = {0, 0, 0} "Initial particle velocity [m/s]";
  parameter Integer seed = 1 "Random seed";
  parameter Modelica.Units.SI.Time tc = simBox.tc "Communication interval";
  output Integer insertedTotal(start = 0, fixed = true) "Particles inserted since the start";
  output Real insertedMass(start = 0, fixed = true) "Mass inserted since the start [kg]";
  output Integer shortfall(start = 0, fixed = true) "Requested but not placed since the start";
protected
  DEMLink.Functions.Client client = DEMLink.Functions.Client();
  parameter Integer handle(fixed = false);
  Integer status(start = 0, fixed = true);
  Integer counts[3](each start = 0, each fixed = true);
  Real masses[3](each start = 0, each fixed = true);
initial algorithm
  DEMLink.Functions.check(client, DEMLink.Functions.connectToHost(client, simBox.address, simBox.port, name, simBox.token));
  handle := DEMLink.Functions.declareParticleSourceBox(client, name, tc, material, centre, halfExtents, rMin, rMax,
    ratePerSecond, rateKgPerSecond, velocity, seed);
algorithm
  when sample(0, tc) then
    (status, counts, masses) := DEMLink.Functions.particleSourceRead(client, handle);
    DEMLink.Functions.check(client, status);
    insertedTotal := counts[2];
    insertedMass := masses[2];
    shortfall := counts[3];
  end when;
  when terminal() then
    DEMLink.Functions.check(client, DEMLink.Functions.finish(client, "terminal()"));
  end when;
end ParticleSource;
