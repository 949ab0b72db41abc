within DEMLink.Interfaces;
partial model PartialFrameBody "A rigid body attached to a Modelica.Mechanics.MultiBody frame"
  extends DEMLink.Interfaces.PartialRigidBody;
  Modelica.Mechanics.MultiBody.Interfaces.Frame_a frame_a
    "At the body's reference point (referencePoint in the geometry frame); receives the particles' wrench"
    annotation (Placement(transformation(extent = {{-116, -16}, {-84, 16}})));
protected
  Modelica.Mechanics.MultiBody.Frames.Quaternions.Orientation Q
    "MultiBody quaternion {p1, p2, p3, p0}: frame_a's orientation relative to world";
  Modelica.Units.SI.Velocity v_0[3] = der(frame_a.r_0) "Velocity of frame_a's origin, world frame";
  Modelica.Units.SI.AngularVelocity w_0[3] = Modelica.Mechanics.MultiBody.Frames.angularVelocity1(frame_a.R)
    "Angular velocity of frame_a, world frame";
equation
  // MultiBody: R.T transforms world to frame_a coordinates, and Q = {n sin(phi/2), cos(phi/2)}
  // for frame_a turned by phi about n relative to world. DEMLink takes the body-to-world
  // rotation (transpose(R.T)) as w x y z: the same rotation by phi about n, so the conversion
  // is only the reordering {p0, p1, p2, p3} (docs/modelica.md).
  Q = Modelica.Mechanics.MultiBody.Frames.to_Q(frame_a.R);
  pose = cat(1, frame_a.r_0, {Q[4], Q[1], Q[2], Q[3]});
  twist = cat(1, v_0, w_0);
  // DEMLink's wrench acts ON the body, world frame; a MultiBody frame's cut force f and
  // torque t (frame_a coordinates) are those the component exerts with the opposite sign,
  // as in Modelica.Mechanics.MultiBody.Forces.WorldForce.
  frame_a.f = -Modelica.Mechanics.MultiBody.Frames.resolve2(frame_a.R, meanForce);
  frame_a.t = -Modelica.Mechanics.MultiBody.Frames.resolve2(frame_a.R, meanTorque);
end PartialFrameBody;
