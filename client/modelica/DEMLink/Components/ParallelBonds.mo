within DEMLink.Components;
model ParallelBonds "Cements touching spheres with parallel bonds (Potyondy and Cundall 2004)"
  extends DEMLink.Interfaces.PartialComponent(name = "bonds", final kind = "parallel_bonds", final exchanged = false,
    final declInts = {seed, Integer(region) - 1}, final declReals = cat(1, {normalStiffnessPerArea,
    shearStiffnessPerArea, tensileStrength, shearStrength, gapTolerance, radiusMultiplier, createTime, fraction},
    centre, if region == DEMLink.Types.BondRegion.Sphere then {radius, 0, 0} else size, orientation),
    final declStrings = cat(1, {attachedTo}, materials));
  parameter Real normalStiffnessPerArea(unit = "Pa/m") = 1e9 "Normal stiffness per area kn";
  parameter Real shearStiffnessPerArea(unit = "Pa/m") = 1e9 "Shear stiffness per area ks";
  parameter Modelica.Units.SI.Pressure tensileStrength = 1e5 "Tensile strength";
  parameter Modelica.Units.SI.Pressure shearStrength = 1e5 "Shear strength (cohesion)";
  parameter Modelica.Units.SI.Length gapTolerance = 1e-3 "Largest surface gap of a bonded pair";
  parameter Real radiusMultiplier(unit = "1") = 1 "Bond radius / smaller sphere radius, in (0, 1]";
  parameter Modelica.Units.SI.Time createTime = 0 "Bonds are made at the first step ending at or after it";
  parameter Real fraction(unit = "1") = 1 "Probability a candidate pair is bonded, in (0, 1]";
  parameter Integer seed = 0 "Random seed of the fraction";
  parameter String materials[:] = {""} "Both spheres of one of these materials (\"\": any)";
  parameter DEMLink.Types.BondRegion region = DEMLink.Types.BondRegion.Everywhere "Where pairs are bonded"
    annotation (Dialog(group = "Region"));
  parameter Modelica.Units.SI.Position centre[3] = {0, 0, 0} "Region centre (body frame when attached)"
    annotation (Dialog(group = "Region", enable = region <> DEMLink.Types.BondRegion.Everywhere));
  parameter Modelica.Units.SI.Length size[3] = {1, 1, 1} "Box edge lengths"
    annotation (Dialog(group = "Region", enable = region == DEMLink.Types.BondRegion.Box));
  parameter Real orientation[4](each unit = "1") = {1, 0, 0, 0} "Box orientation, quaternion w x y z"
    annotation (Dialog(group = "Region", enable = region == DEMLink.Types.BondRegion.Box));
  parameter Modelica.Units.SI.Radius radius = 0.5 "Sphere radius"
    annotation (Dialog(group = "Region", enable = region == DEMLink.Types.BondRegion.Sphere));
  parameter String attachedTo = "" "Rigid body the region rides on (empty: fixed)"
    annotation (Dialog(group = "Region", enable = region <> DEMLink.Types.BondRegion.Everywhere));
  annotation (Documentation(info = "<html><p>The scene's <code>parallel_bonds</code> component
(docs/reference/parallel_bonds.md), declared only: the server makes the bonds at
<code>createTime</code> between every pair of spheres of the named materials whose surfaces are at
most <code>gapTolerance</code> apart, and checks every value when it compiles the scene. Named by a
PitGenerator's <code>clodBonds</code>, it bonds only within that pit's clods. With
<code>region</code> Box or Sphere it bonds only the pairs whose centres are both inside,
in the frame of <code>attachedTo</code>'s body when given. A RegionSensor's
<code>bondsIntact</code> and <code>bondsBroken</code> count the bonds in its region.</p></html>"));
end ParallelBonds;
