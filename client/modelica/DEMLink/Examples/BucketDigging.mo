within DEMLink.Examples;
model BucketDigging "A bucket (CADPart) drawn through a gravel pit on a prescribed path; a sensor on the bucket weighs its fill"
  extends Modelica.Icons.Example;
  import Modelica.Constants.pi;
  // Bounds wide enough that gravel the bucket throws sideways, rolling on the floor at up
  // to ~0.7 m/s, stays inside for the whole pass: the example checks that no mass is lost.
  inner DEMLink.Basics.SimulationBox simBox(tc = 2e-3, timeout = 120, boundsLower = {-1, -1, -0.05},
    boundsUpper = {1, 1, 0.6}) annotation (Placement(transformation(extent = {{-90, 60}, {-70, 80}})));
  DEMLink.Components.Material gravel(name = "gravel", databaseName = "gravel")
    annotation (Placement(transformation(extent = {{-60, 60}, {-40, 80}})));
  DEMLink.Components.Plane floor(name = "floor", point = {0, 0, 0}, normal = {0, 0, 1}, material = "gravel")
    annotation (Placement(transformation(extent = {{-30, 60}, {-10, 80}})));
  DEMLink.Components.PitGenerator pit(name = "pit", material = "gravel", lower = {-0.15, -0.07, 0},
    upper = {0.15, 0.07, 0.1}, rMin = 0.008, rMax = 0.01, targetHeight = 0.07, seed = 1)
    annotation (Placement(transformation(extent = {{0, 60}, {20, 80}})));
  DEMLink.Components.CADPart bucket(name = "bucket", fileName = "modelica://DEMLink/Resources/Data/bucket.stl",
    material = "gravel", initialPosition = {x0, 0, z0}) annotation (Placement(transformation(extent = {{-10, -10}, {10, 10}})));
  DEMLink.Sensors.RegionSensor fill(name = "fill", attachedTo = "bucket", centre = {0, 0, 0.03}, size = {0.12, 0.1, 0.06})
    "The bucket's inside, moving with it" annotation (Placement(transformation(extent = {{30, -10}, {50, 10}})));
  DEMLink.Visualization.DEMPoints points(name = "points", maxCount = 100, viewPoint = {0, -0.8, 0.5}, lodDistance = 0.9)
    "Spheres on the near side of the bed, diamonds beyond (set viewPoint to the camera's position)"
    annotation (Placement(transformation(extent = {{30, 60}, {50, 80}})));
  parameter Modelica.Units.SI.Time T = 0.6 "Duration of the pass";
  parameter Modelica.Units.SI.Position x0 = -0.2 "Start of the pass (bucket floor centre)";
  parameter Modelica.Units.SI.Length stroke = 0.4 "Length of the pass";
  parameter Modelica.Units.SI.Position z0 = 0.11 "Height of the bucket floor at the start and end (clear of the bed)";
  parameter Modelica.Units.SI.Length depth = 0.07 "Deepest dip below z0";
equation
  bucket.position = {x0 + stroke * time / T, 0, z0 - depth * sin(pi * time / T)};
  bucket.velocity = {stroke / T, 0, -depth * pi / T * cos(pi * time / T)};
  bucket.orientation = {1, 0, 0, 0};
  bucket.angularVelocity = {0, 0, 0};
  annotation (experiment(StopTime = 0.6, Interval = 0.002), Documentation(info = "<html>
<p>The excavator use case of the coupling paper (section 6.1), reduced to its bucket: a
120 x 100 x 60 mm scoop, open at the top and the front, drawn 0.4 m along x through a
settled gravel bed (PitGenerator, 70 mm) and dipping 70 mm on a half sine, to 40 mm above
the floor. The bucket's
outputs give the digging force; the RegionSensor attached to the bucket weighs its fill;
DEMPoints shows 100 of the particles. Start <code>demlink-server --port 47000</code> first.
tests/modelica/bucket_digging_sequence.c makes this model's calls against a real server
and checks the force and the fill.</p></html>"));
end BucketDigging;
