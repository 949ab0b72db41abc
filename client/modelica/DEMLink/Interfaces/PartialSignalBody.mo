within DEMLink.Interfaces;
partial model PartialSignalBody "A rigid body driven by signals: pose and twist of its reference point in DEMLink's conventions"
  extends DEMLink.Interfaces.PartialRigidBody;
  Modelica.Blocks.Interfaces.RealInput position[3](each unit = "m") "Reference point, world frame"
    annotation (Placement(transformation(extent = {{-140, 40}, {-100, 80}})));
  Modelica.Blocks.Interfaces.RealInput orientation[4] "Quaternion w x y z (scalar first), body to world"
    annotation (Placement(transformation(extent = {{-140, 0}, {-100, 40}})));
  Modelica.Blocks.Interfaces.RealInput velocity[3](each unit = "m/s") "Reference point velocity, world frame"
    annotation (Placement(transformation(extent = {{-140, -40}, {-100, 0}})));
  Modelica.Blocks.Interfaces.RealInput angularVelocity[3](each unit = "rad/s") "World frame"
    annotation (Placement(transformation(extent = {{-140, -80}, {-100, -40}})));
equation
  pose = cat(1, position, orientation);
  twist = cat(1, velocity, angularVelocity);
end PartialSignalBody;
