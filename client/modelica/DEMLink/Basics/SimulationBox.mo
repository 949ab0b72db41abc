within DEMLink.Basics;
model SimulationBox "Server address, communication interval and the DEM run's settings (use as inner simBox)"
  parameter String address = "127.0.0.1" "Host of demlink-server" annotation (Dialog(group = "Server"));
  parameter Integer port = 47000 "TCP port of demlink-server (its --port)" annotation (Dialog(group = "Server"));
  parameter String token = "" "Access token when the server requires one" annotation (Dialog(group = "Server"));
  parameter Modelica.Units.SI.Time timeout = 30 "Longest wait for the server in one call" annotation (Dialog(group = "Server"));
  parameter Modelica.Units.SI.Time tc = 1e-3 "Communication interval of the components" annotation (Dialog(group = "Coupling"));
  parameter Integer nComponents = 0
    "0: the server compiles when every component's initialisation has ended (none to count); > 0: also wait for this many components, this box included"
    annotation (Dialog(group = "Coupling"));
  parameter Modelica.Units.SI.Time timeStep = -1 "DEM time step (negative: the server's limit from the materials)";
  parameter Modelica.Units.SI.Time endTime = 0
    "DEM end time; 0: the DEM run ends with this model's run (every component's Bye at terminal())";
  parameter Modelica.Units.SI.Acceleration gravity[3] = {0, 0, -9.81} "Gravity";
  parameter Modelica.Units.SI.Position boundsLower[3] = {-5, -5, -5} "Lower corner of the DEM domain (particles leaving it are removed)";
  parameter Modelica.Units.SI.Position boundsUpper[3] = {5, 5, 5} "Upper corner of the DEM domain";
  parameter Modelica.Units.SI.Time vtkInterval = -1 "VTK output interval of the server (negative: the server's default)"
    annotation (Dialog(group = "Server output"));
  parameter Integer threads = -1 "Engine threads (negative: 1, 0: automatic, the usable CPUs less the load average)" annotation (Dialog(group = "Speed and accuracy"));
  parameter DEMLink.Types.Fidelity fidelity = DEMLink.Types.Fidelity.NoPreset
    "Preset for the speed/accuracy settings left at their default" annotation (Dialog(group = "Speed and accuracy"));
  parameter DEMLink.Types.ContactModel contactModel = DEMLink.Types.ContactModel.Default "Contact law"
    annotation (Dialog(group = "Speed and accuracy"));
  parameter DEMLink.Types.Integrator integrator = DEMLink.Types.Integrator.Default "Time integrator"
    annotation (Dialog(group = "Speed and accuracy"));
  parameter Real restitutionTolerance(unit = "1") = -1
    "Largest restitution error the server's time-step limit allows (negative: 0.01 or the preset's); larger accepts a larger timeStep (trades accuracy for speed)"
    annotation (Dialog(group = "Speed and accuracy"));
  parameter Modelica.Units.SI.Velocity maxImpactVelocity = -1
    "Largest expected impact speed, for the time-step limit (negative: 2 m/s)" annotation (Dialog(group = "Speed and accuracy"));
  parameter Real coarseGraining(unit = "1") = -1
    "Parcels of this factor times the grains' size from lattices and sources, same mass flow (negative: 1, none)"
    annotation (Dialog(group = "Speed and accuracy"));
  parameter Real modulusScale(unit = "1") = -1
    "Softening factor of every Young's modulus for the contacts, in (0, 1]: a larger time step, a softer material (negative: 1, none)"
    annotation (Dialog(group = "Speed and accuracy"));
  parameter String expectedNames[:] = fill("", 0)
    "Names of components the server waits for besides the count (e.g. those of another tool's clients)"
    annotation (Dialog(group = "Coupling"));
  parameter Boolean useGravityInput = false "Gravity from the input gravityIn (a tilting or accelerating frame)";
  Modelica.Blocks.Interfaces.RealInput gravityIn[3](each unit = "m/s2") if useGravityInput
    "Gravity, world frame, sent at every sample" annotation (Placement(transformation(extent = {{-140, -20}, {-100, 20}})));
  parameter Boolean useFrameInput = false
    "Frame motion from the inputs frameAcceleration, frameAngularVelocity, frameAngularAcceleration (a moving frame)";
  parameter Modelica.Units.SI.Position frameOrigin[3] = {0, 0, 0} "Point the frame rotates about (useFrameInput)"
    annotation (Dialog(enable = useFrameInput));
  Modelica.Blocks.Interfaces.RealInput frameAcceleration[3](each unit = "m/s2") if useFrameInput
    "Linear acceleration of the moving frame, sent at every sample" annotation (Placement(transformation(extent = {{-140, 40}, {-100, 80}})));
  Modelica.Blocks.Interfaces.RealInput frameAngularVelocity[3](each unit = "rad/s") if useFrameInput
    "Angular velocity of the moving frame" annotation (Placement(transformation(extent = {{-140, -60}, {-100, -20}})));
  Modelica.Blocks.Interfaces.RealInput frameAngularAcceleration[3](each unit = "rad/s2") if useFrameInput
    "Angular acceleration of the moving frame" annotation (Placement(transformation(extent = {{-140, -100}, {-100, -60}})));
  Modelica.Blocks.Interfaces.IntegerOutput particleCount(start = 0, fixed = true) "Particles in the DEM world"
    annotation (Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Modelica.Blocks.Interfaces.RealOutput totalMass(unit = "kg", start = 0, fixed = true) "Mass of all particles"
    annotation (Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Modelica.Blocks.Interfaces.RealOutput kineticEnergy(unit = "J", start = 0, fixed = true) "Kinetic energy of all particles"
    annotation (Placement(transformation(extent = {{100, -30}, {120, -10}})));
  Modelica.Blocks.Interfaces.RealOutput demTime(unit = "s", start = 0, fixed = true) "DEM time at the end of the last interval"
    annotation (Placement(transformation(extent = {{100, -70}, {120, -50}})));
  Modelica.Blocks.Interfaces.RealOutput stepRate(unit = "1/s", start = 0, fixed = true) "DEM steps per wall-clock second";
protected
  Modelica.Blocks.Interfaces.RealInput gravityNow[3] "gravityIn or the gravity parameter";
  Modelica.Blocks.Interfaces.RealInput frameNow[9] "The frame inputs, or zeros";
  DEMLink.Functions.Client client = DEMLink.Functions.Client(address, port, "simBox", token, timeout);
  Integer status(start = 0, fixed = true);
  Integer samplesSent(start = 0, fixed = true) "Samples whose inputs were sent (each sample's first call)";
  Integer samplesReceived(start = 0, fixed = true) "Samples whose outputs were received (the second call)";
  Real out[4](each start = 0, each fixed = true);
initial algorithm
  DEMLink.Functions.connectClient(client, address, port, "simBox", token, timeout);
  DEMLink.Functions.declare(client, "simulation_box", "simBox", tc, {nComponents, threads, Integer(contactModel) - 1,
    Integer(integrator) - 1, Integer(fidelity) - 1}, cat(1, {DEMLink.Functions.optional(timeStep), endTime}, gravity,
    boundsLower, boundsUpper, {DEMLink.Functions.optional(vtkInterval), DEMLink.Functions.optional(restitutionTolerance),
    DEMLink.Functions.optional(maxImpactVelocity), DEMLink.Functions.optional(coarseGraining),
    DEMLink.Functions.optional(-1), DEMLink.Functions.optional(modulusScale)}), expectedNames);
  DEMLink.Functions.declarationsDone(client);
equation
  connect(gravityIn, gravityNow);
  if not useGravityInput then
    gravityNow = gravity;
  end if;
  connect(frameAcceleration, frameNow[1:3]);
  connect(frameAngularVelocity, frameNow[4:6]);
  connect(frameAngularAcceleration, frameNow[7:9]);
  if not useFrameInput then
    frameNow = zeros(9);
  end if;
algorithm
  when sample(0, tc) then
    if useFrameInput then
      // One-shot input: sent with this sample's package, applied from its step on.
      status := DEMLink.Functions.External.simulationBoxSetFrame(client, 0, frameNow[1:3], frameNow[4:6],
        frameNow[7:9], frameOrigin);
      DEMLink.Functions.checkExchange(client, status);
    end if;
    // The sample's first call sends the inputs at t (send first; docs/modelica.md, "How a component runs").
    (status, out, particleCount) := DEMLink.Functions.External.simulationBoxExchange(client, 0, gravityNow);
    DEMLink.Functions.checkExchange(client, status);
    samplesSent := pre(samplesSent) + 1;
  end when;
  when pre(samplesSent) > pre(samplesReceived) then
    // The event iteration after every component's first call: this one returns [t, t + tc].
    (status, out, particleCount) := DEMLink.Functions.External.simulationBoxExchange(client, 0, gravityNow);
    DEMLink.Functions.checkExchange(client, status);
    samplesReceived := pre(samplesSent);
    demTime := out[1];
    totalMass := out[2];
    kineticEnergy := out[3];
    stepRate := out[4];
  end when;
  when terminal() then
    DEMLink.Functions.finish(client);
  end when;
  annotation (defaultComponentName = "simBox", defaultComponentPrefixes = "inner",
    missingInnerMessage = "Add an inner DEMLink.Basics.SimulationBox simBox to the model.",
    Icon(graphics = {Rectangle(extent = {{-100, 100}, {100, -100}}, lineColor = {95, 75, 45}, fillColor = {250, 245, 230},
      fillPattern = FillPattern.Solid), Rectangle(extent = {{-70, 60}, {70, -70}}, lineColor = {95, 75, 45},
      pattern = LinePattern.Dash), Text(extent = {{-150, 140}, {150, 105}}, textString = "%name", textColor = {0, 0, 255})}),
    Documentation(info = "<html>
<p>Exactly one <code>inner SimulationBox simBox</code> per model, like the MultiBody
<code>world</code>: every component reaches the server address, port and communication
interval through <code>outer simBox</code>. The box declares the DEM run's settings (time
step, gravity, bounds, VTK output interval, and the speed/accuracy settings: engine
threads, fidelity preset, contact law, integrator, restitution tolerance, largest impact
speed, coarse graining, modulus scale) and the names of components the server waits for besides this
model's own (<code>expectedNames</code>, e.g. another tool's clients). The model's own components are not counted: each says at the end of its
initialisation that its declarations are done, and the server compiles once every
connected client has said so. With <code>useGravityInput</code> the gravity follows the input
<code>gravityIn</code> at every sample (the paper's accelerated and tilting frames, section
6.2, as far as a gravity vector expresses them). With <code>useFrameInput</code> the frame
itself moves: its linear acceleration, angular velocity and angular acceleration (about
<code>frameOrigin</code>) follow the frame inputs at every sample, and the particles feel the
fictitious forces of that frame (docs/frame_and_facets.md).</p>
<p>With <code>endTime = 0</code> (the default) the DEM run lasts exactly as long as the
model's run: it ends when every component has said Bye at <code>terminal()</code>.</p></html>"));
end SimulationBox;
