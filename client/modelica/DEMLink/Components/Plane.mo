within DEMLink.Components;
model Plane "An infinite wall (no feedback to the system model)"
  extends DEMLink.Interfaces.PartialComponent(name = "ground", final kind = "plane", final exchanged = false,
    final declInts = fill(0, 0), final declReals = cat(1, point, normal), final declStrings = {material});
  parameter Modelica.Units.SI.Position point[3] = {0, 0, 0} "A point on the plane";
  parameter Real normal[3](each unit = "1") = {0, 0, 1} "Normal towards the particles' side";
  parameter String material = "gravel" "Material name";
end Plane;
