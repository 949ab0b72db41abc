within DEMLink.Components;
model ClumpTemplate "A multisphere particle shape that ParticleSource and PitGenerator can pour"
  extends DEMLink.Interfaces.PartialComponent(name = "clump", final kind = "clump_template", final exchanged = false,
    final declInts = fill(0, 0),
    final declReals = {spheres[div(i - 1, 4) + 1, mod(i - 1, 4) + 1] for i in 1:4 * size(spheres, 1)},
    final declStrings = fill("", 0));
  parameter Modelica.Units.SI.Length spheres[:, 4] = {{-0.002, 0, 0, 0.003}, {0.002, 0, 0, 0.003}}
    "Member spheres, one row each: x, y, z offset from the clump's reference point and radius";
  annotation (Documentation(info = "<html><p>A rigid clump of overlapping spheres (the scene's
<code>clump_template</code>; docs/reference/clump_template.md). Name it in a ParticleSource's or
a PitGenerator's <code>clumpTemplate</code> to pour clumps of this shape instead of spheres.
<code>demlink-clump-fit SHAPE.stl --spheres N</code> writes the rows for a closed STL solid.</p></html>"));
end ClumpTemplate;
