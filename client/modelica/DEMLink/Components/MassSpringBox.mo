within DEMLink.Components;
model MassSpringBox "A box-shaped mass-spring body (node lattice joined by springs that break)"
  extends DEMLink.Interfaces.PartialDeformableBody(name = "springs");
  parameter Modelica.Units.SI.Position lo[3] = {-0.1, -0.1, 0} "Lower corner of the node lattice";
  parameter Modelica.Units.SI.Position hi[3] = {0.1, 0.1, 0.05} "Upper corner of the node lattice";
  parameter Modelica.Units.SI.Length nodeSpacing = 0.025 "Node spacing";
  parameter Modelica.Units.SI.Mass totalMass = 1 "Mass of all nodes";
  parameter Modelica.Units.SI.TranslationalSpringConstant stiffness = 1e4 "Spring stiffness";
  parameter Modelica.Units.SI.TranslationalDampingConstant damping = 1 "Spring damping";
  parameter Modelica.Units.SI.Force breakForce = -1 "A spring breaks above this force (negative: never)";
  parameter Real breakStrain(unit = "1") = -1 "A spring breaks above this strain (negative: never)";
initial algorithm
  DEMLink.Functions.connectClient(client, simBox.address, simBox.port, name, simBox.token, simBox.timeout);
  (declareStatus, handle) := DEMLink.Functions.External.declareMassSpringBox(client, name, tc, material, lo, hi, nodeSpacing,
    {totalMass, stiffness, damping}, {breakForce, breakStrain}, div(size(fixedRegions, 1), 6), fixedRegions,
    div(size(drivenRegions, 1), 6), drivenRegions, drivenReference, attachedTo);
  DEMLink.Functions.check(client, declareStatus);
  DEMLink.Functions.declarationsDone(client);
  annotation (Documentation(info = "<html><p>The mass-spring body of the solver paper
(BMEDEM3D): nodes on a lattice filling [lo, hi], springs between neighbours that break
above <code>breakForce</code> or <code>breakStrain</code>. Declared with
<code>dl_declare_mass_spring_box</code>.</p></html>"));
end MassSpringBox;
