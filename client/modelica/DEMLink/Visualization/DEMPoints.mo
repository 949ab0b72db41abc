within DEMLink.Visualization;
model DEMPoints
  "Decimated particle view: positions and radii of at most maxCount particles, drawn as splats, diamonds or spheres"
  extends DEMLink.Interfaces.PartialComponent(name = "points", final kind = "particle_view", final exchanged = true,
    final declInts = {maxCount}, final declReals = fill(0.0, 0), final declStrings = fill("", 0));
  parameter Integer maxCount(min = 1) = 200
    "Most particles shown (the server lists those whose id is a multiple of a stride: the same ones at every sample)";
  parameter Boolean animation = true "Draw the particles (MultiBody animation)";
  parameter Integer maxShapes(min = 1) = maxCount
    "Most particles drawn (an even stride over the listed rows, so the drawn ones spread over all ids)"
    annotation (Dialog(group = "Animation", enable = animation));
  parameter DEMLink.Types.PointStyle style = DEMLink.Types.PointStyle.Auto "Shape of each drawn particle"
    annotation (Dialog(group = "Animation", enable = animation));
  parameter Modelica.Units.SI.Position viewPoint[3] = {0, -3, 2}
    "Eye position of the 3D view, world frame: splats and diamonds face it, Auto measures distances from it"
    annotation (Dialog(group = "Animation", enable = animation));
  parameter Modelica.Units.SI.Distance lodDistance(min = 0) = 2
    "Auto: particles nearer than this to viewPoint are spheres"
    annotation (Dialog(group = "Animation", enable = animation and style == DEMLink.Types.PointStyle.Auto));
  parameter Modelica.Units.SI.Distance splatDistance(min = 0) = 2 * lodDistance
    "Auto: particles from lodDistance to this are diamonds, farther ones splats"
    annotation (Dialog(group = "Animation", enable = animation and style == DEMLink.Types.PointStyle.Auto));
  parameter Real flatness(unit = "1", min = 0) = 0.1 "Thickness of a splat or diamond over the particle diameter"
    annotation (Dialog(group = "Animation", enable = animation));
  parameter Modelica.Mechanics.MultiBody.Types.Color color = {160, 130, 90} "Colour of every shape"
    annotation (Dialog(group = "Animation", enable = animation));
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
  final parameter Integer shapeCount = min(maxShapes, maxCount) "Shapes of each kind";
  Integer rowStride(start = 1, fixed = true) "Listed rows per drawn particle: count over shapeCount, rounded up";
  Integer row(start = 1, fixed = true) "Listed row of the drawn particle being classified";
  // Every drawn particle has one shape of each kind; the two kinds it is not drawn as have size 0,
  // so the level of detail changes at run time without a shapeType that varies.
  Modelica.Units.SI.Position shapeCentre[shapeCount, 3](each start = 0, each fixed = true) "Drawn particle's centre";
  Real toEye[shapeCount, 3](each unit = "1", each start = 0, each fixed = true)
    "Unit vector from the drawn particle to viewPoint (the normal of its splat or diamond)";
  Modelica.Units.SI.Diameter sphereDiameter[shapeCount](each start = 0, each fixed = true) "0: not drawn as a sphere";
  Modelica.Units.SI.Length diamondSide[shapeCount](each start = 0, each fixed = true)
    "sqrt(2) * radius, so the tips lie on the particle's outline; 0: not drawn as a diamond";
  Modelica.Units.SI.Diameter splatDiameter[shapeCount](each start = 0, each fixed = true) "0: not drawn as a splat";
  Modelica.Units.SI.Length diamondThickness[shapeCount](each start = 0, each fixed = true);
  Modelica.Units.SI.Length splatThickness[shapeCount](each start = 0, each fixed = true);
  Modelica.Units.SI.Distance eyeDistance(start = 0, fixed = true) "Of the drawn particle being classified";
  DEMLink.Types.PointStyle drawnAs(start = DEMLink.Types.PointStyle.Sphere, fixed = true)
    "Style of the drawn particle being classified (never Auto)";
  Modelica.Mechanics.MultiBody.Visualizers.Advanced.Shape spheres[shapeCount](each shapeType = "sphere",
    r = shapeCentre, r_shape = {{-sphereDiameter[k] / 2, 0, 0} for k in 1:shapeCount}, each lengthDirection = {1, 0, 0},
    each widthDirection = {0, 1, 0}, length = sphereDiameter, width = sphereDiameter, height = sphereDiameter,
    each color = color, each R = Modelica.Mechanics.MultiBody.Frames.nullRotation()) if animation;
  // A thin box along toEye whose width direction is world z turned 45 degrees about toEye: seen
  // from viewPoint, a square standing on a corner. Straight above or below, any turn will do.
  Modelica.Mechanics.MultiBody.Visualizers.Advanced.Shape diamonds[shapeCount](each shapeType = "box",
    r = shapeCentre, r_shape = {-diamondThickness[k] / 2 * toEye[k, :] for k in 1:shapeCount}, lengthDirection = toEye,
    widthDirection = {{0, 0, 1} + cross(toEye[k, :], {0, 0, 1}) for k in 1:shapeCount}, length = diamondThickness,
    width = diamondSide, height = diamondSide, each color = color,
    each R = Modelica.Mechanics.MultiBody.Frames.nullRotation()) if animation;
  Modelica.Mechanics.MultiBody.Visualizers.Advanced.Shape splats[shapeCount](each shapeType = "cylinder",
    r = shapeCentre, r_shape = {-splatThickness[k] / 2 * toEye[k, :] for k in 1:shapeCount}, lengthDirection = toEye,
    each widthDirection = {0, 0, 1}, length = splatThickness, width = splatDiameter, height = splatDiameter,
    each color = color, each R = Modelica.Mechanics.MultiBody.Frames.nullRotation()) if animation;
equation
  assert(splatDistance >= lodDistance, "DEMPoints " + name + ": splatDistance = " + String(splatDistance)
    + " m is below lodDistance = " + String(lodDistance) + " m");
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
    rowStride := max(1, div(count + shapeCount - 1, shapeCount));
    for k in 1:shapeCount loop
      // Past count (even past maxCount for the last shapes): no shape of any kind; min keeps the
      // index in bounds in the branch not taken.
      row := (k - 1) * rowStride + 1;
      shapeCentre[k, :] := if row <= count then positions[min(row, maxCount), :] else zeros(3);
      eyeDistance := Modelica.Math.Vectors.length(viewPoint - shapeCentre[k, :]);
      toEye[k, :] := if eyeDistance > 0 then (viewPoint - shapeCentre[k, :]) / eyeDistance else {0, 0, 1};
      drawnAs := if style <> DEMLink.Types.PointStyle.Auto then style
        elseif eyeDistance < lodDistance then DEMLink.Types.PointStyle.Sphere
        elseif eyeDistance < splatDistance then DEMLink.Types.PointStyle.Diamond
        else DEMLink.Types.PointStyle.Splat;
      sphereDiameter[k] := if drawnAs == DEMLink.Types.PointStyle.Sphere and row <= count then
        2 * radii[min(row, maxCount)] else 0;
      diamondSide[k] := if drawnAs == DEMLink.Types.PointStyle.Diamond and row <= count then
        sqrt(2) * radii[min(row, maxCount)] else 0;
      diamondThickness[k] := flatness * sqrt(2) * diamondSide[k];
      splatDiameter[k] := if drawnAs == DEMLink.Types.PointStyle.Splat and row <= count then
        2 * radii[min(row, maxCount)] else 0;
      splatThickness[k] := flatness * splatDiameter[k];
    end for;
  end when;
  annotation (Documentation(info = "<html><p>The coupling paper's DEMPoints (section 5.1): one
animation shape per listed particle would be too many for a whole bed, so the server lists
at most <code>maxCount</code> of them: those whose id is a multiple of a stride (the
largest id over maxCount, rounded up), in increasing id order, so a row of
<code>positions</code>, <code>velocities</code> and <code>ids</code> follows the same
particle from sample to sample whatever the engine's storage order.</p>
<p>With <code>animation</code>, at most <code>maxShapes</code> of the listed rows, an even
stride over them, are drawn with MultiBody shapes, each sized by its particle's radius, in
the shape
<code>style</code> names: a sphere, a diamond (a thin square turned 45 degrees) or a splat
(a thin disc), the flat ones facing <code>viewPoint</code>. With <code>Auto</code>, a
particle nearer than <code>lodDistance</code> to <code>viewPoint</code> is a sphere, one
nearer than <code>splatDistance</code> a diamond, any other a splat; the choice is made
again at every sample. For more than about 1e5 particles, watch the server's live view
(<code>demlink-server --view 127.0.0.1:PORT</code>, docs/view.md) instead.</p></html>"));
end DEMPoints;
