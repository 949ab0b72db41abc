within DEMLink.Visualization;
model DEMPoints "Decimated particle view: positions and radii of at most maxCount particles, animated as spheres"
  extends DEMLink.Interfaces.PartialComponent(name = "points", final kind = "particle_view", final exchanged = true,
    final declInts = {maxCount}, final declReals = fill(0.0, 0), final declStrings = fill("", 0));
  parameter Integer maxCount(min = 1) = 200
    "Most particles shown (the server lists those whose id is a multiple of a stride: the same ones at every sample)";
  parameter Boolean animation = true "Show the particles as spheres (MultiBody animation)";
  parameter Modelica.Mechanics.MultiBody.Types.Color color = {160, 130, 90} "Sphere colour";
  Modelica.Blocks.Interfaces.IntegerOutput count(start = 0, fixed = true) "Particles listed (at most maxCount)"
    annotation (Placement(transformation(extent = {{100, -10}, {120, 10}})));
  Modelica.Units.SI.Position positions[maxCount, 3](each start = 0, each fixed = true) "Centres, world frame";
  Modelica.Units.SI.Radius radii[maxCount](each start = 0, each fixed = true) "Radii (0: not listed)";
  Modelica.Units.SI.Velocity velocities[maxCount, 3](each start = 0, each fixed = true) "Velocities, world frame";
  Integer ids[maxCount](each start = 0, each fixed = true) "The listed particles' ids, increasing (-1: above 2^31 - 1; rows beyond count: 0)";
protected
  Integer status(start = 0, fixed = true);
  Integer samplesSent(start = 0, fixed = true) "Samples whose inputs were sent (each sample's first call)";
  Integer samplesReceived(start = 0, fixed = true) "Samples whose outputs were received (the second call)";
  Real flat[3 * maxCount](each start = 0, each fixed = true);
  Real flatVelocities[3 * maxCount](each start = 0, each fixed = true);
  Integer listedIds[maxCount](each start = 0, each fixed = true);
  Real listed[maxCount](each start = 0, each fixed = true);
  Modelica.Mechanics.MultiBody.Visualizers.Advanced.Shape spheres[maxCount](each shapeType = "sphere",
    r = positions, r_shape = {{-radii[i], 0, 0} for i in 1:maxCount}, each lengthDirection = {1, 0, 0},
    each widthDirection = {0, 1, 0}, length = 2 * radii, width = 2 * radii, height = 2 * radii,
    each color = color, each R = Modelica.Mechanics.MultiBody.Frames.nullRotation()) if animation;
algorithm
  when sample(0, tc) then
    // The sample's first call sends the inputs at t (send first; docs/modelica.md, "How a component runs").
    (status, flat, flatVelocities, listed, listedIds, count) := DEMLink.Functions.External.particleViewRead(client, 0,
      maxCount);
    DEMLink.Functions.checkExchange(client, status);
    samplesSent := pre(samplesSent) + 1;
  end when;
  when pre(samplesSent) > pre(samplesReceived) then
    // The event iteration after every component's first call: this one returns [t, t + tc].
    (status, flat, flatVelocities, listed, listedIds, count) := DEMLink.Functions.External.particleViewRead(client, 0,
      maxCount);
    DEMLink.Functions.checkExchange(client, status);
    samplesReceived := pre(samplesSent);
    for i in 1:maxCount loop
      positions[i, :] := if i <= count then flat[3 * i - 2:3 * i] else zeros(3);
      velocities[i, :] := if i <= count then flatVelocities[3 * i - 2:3 * i] else zeros(3);
      radii[i] := if i <= count then listed[i] else 0;
      ids[i] := if i <= count then listedIds[i] else 0;
    end for;
  end when;
  annotation (Documentation(info = "<html><p>The coupling paper's DEMPoints (section 5.1): one
animation shape per listed particle would be too many for a whole bed, so the server lists
at most <code>maxCount</code> of them: those whose id is a multiple of a stride (the
largest id over maxCount, rounded up), in increasing id order, so a row of
<code>positions</code>, <code>velocities</code> and <code>ids</code> follows the same
particle from sample to sample whatever the engine's storage order.</p></html>"));
end DEMPoints;
