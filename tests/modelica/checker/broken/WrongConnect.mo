// expect: 13: connect(step.y, body.frame_a): Modelica.Blocks.Interfaces.RealOutput and Modelica.Mechanics.MultiBody.Interfaces.Frame_a are not compatible connectors
// expect: 14: connect(step.y, other.y): two outputs connected
// expect: 15: connect(source.y, part.u): 2 elements connected to 3
// expect: 16: connect: part.v: v is no component of ValidLib.Part
within ValidLib;
model WrongConnect "A signal to a frame, two outputs, sizes that differ, a connector that does not exist"
  Modelica.Blocks.Sources.Step step;
  Modelica.Blocks.Sources.Step other;
  Modelica.Blocks.Sources.Constant source[2](k = {1, 2});
  Modelica.Mechanics.MultiBody.Parts.Body body(m = 1);
  ValidLib.Part part;
equation
  connect(step.y, body.frame_a);
  connect(step.y, other.y);
  connect(source.y, part.u);
  connect(step.y, part.v);
end WrongConnect;
