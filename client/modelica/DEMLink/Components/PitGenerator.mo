within DEMLink.Components;
model PitGenerator "Fills a box with a settled bed of particles before the run"
  extends DEMLink.Interfaces.PartialComponent(name = "pit", final kind = "pit_generator", final exchanged = false,
    final declInts = {seed}, final declReals = cat(1, lower, upper, {rMin, rMax, targetHeight, clodFraction, clodRadius}),
    final declStrings = {material, clodBonds, clumpTemplate});
  parameter String material = "gravel" "Material name";
  parameter Modelica.Units.SI.Position lower[3] = {-3, -1, -1} "Lower corner of the box";
  parameter Modelica.Units.SI.Position upper[3] = {3, 1, 0} "Upper corner of the box";
  parameter Modelica.Units.SI.Radius rMin = 0.04 "Smallest radius";
  parameter Modelica.Units.SI.Radius rMax = 0.05 "Largest radius";
  parameter Modelica.Units.SI.Height targetHeight = 1 "Bed height above the box's floor";
  parameter Integer seed = 1 "Random seed";
  parameter Real clodFraction(unit = "1") = 0 "Fraction of the bed's spheres grouped into clods (0: none)";
  parameter Modelica.Units.SI.Radius clodRadius = 0 "Clod radius (> 0 with clods)";
  parameter String clodBonds = "" "Name of the ParallelBonds component that joins the clods";
  parameter String clumpTemplate = "" "Name of a ClumpTemplate component: a bed of clumps (empty: spheres)";
  annotation (Documentation(info = "<html><p>The pit of the coupling paper's excavator use case
(section 6.1): the server rains and settles the bed when it compiles the scene, before the
first exchange. Give the floor (and walls) as Plane components. With <code>clodFraction</code> &gt; 0
that fraction of the settled spheres is grouped into clods of about <code>clodRadius</code>, joined by
the bonds of the ParallelBonds component <code>clodBonds</code>.</p></html>"));
end PitGenerator;
