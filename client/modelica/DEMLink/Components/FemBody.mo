within DEMLink.Components;
model FemBody "A linear finite-element body from a Gmsh mesh on the server"
  extends DEMLink.Interfaces.PartialDeformableBody(name = "fem");
  parameter String mshFile = "beam.msh" "Gmsh .msh file on the SERVER (below its data root)";
  parameter Modelica.Units.SI.ModulusOfElasticity youngsModulus = 1e7 "Young's modulus";
  parameter Real poissonRatio(unit = "1") = 0.3 "Poisson ratio";
  parameter Modelica.Units.SI.Density density = 1000 "Density";
  parameter Real rayleighAlpha(unit = "s") = 0 "Rayleigh damping C = alpha K + beta M: alpha";
  parameter Real rayleighBeta(unit = "1/s") = 0 "Rayleigh damping: beta";
initial algorithm
  DEMLink.Functions.connectClient(client, simBox.address, simBox.port, name, simBox.token, simBox.timeout);
  (declareStatus, handle) := DEMLink.Functions.External.declareFemMesh(client, name, tc, material, mshFile,
    {youngsModulus, poissonRatio, density}, {rayleighAlpha, rayleighBeta}, div(size(fixedRegions, 1), 6), fixedRegions,
    div(size(drivenRegions, 1), 6), drivenRegions, drivenReference, attachedTo);
  DEMLink.Functions.check(client, declareStatus);
  DEMLink.Functions.declarationsDone(client);
  annotation (Documentation(info = "<html><p>The linear FEM body of the solver paper
(BMEDEM3D) from a Gmsh mesh on the server. Declared with
<code>dl_declare_fem_mesh</code>.</p></html>"));
end FemBody;
