within DEMLink;
package Types "Choices of the DEMLink components"
  extends Modelica.Icons.TypesPackage;
  type RegionShape = enumeration(Box "Box (centre, size, orientation)", Sphere "Sphere (centre, radius)")
    "Shape of a region sensor or particle sink";
  type BondRegion = enumeration(Everywhere "Every pair", Box "Pairs with both centres in a box (centre, size, orientation)",
    Sphere "Pairs with both centres in a sphere (centre, radius)") "Where a ParallelBonds rule bonds";
  type FlowShape = enumeration(Rectangle "Rectangle (centre, normal, length, width, length axis)", Disc "Disc (centre, normal, radius)")
    "Shape of a flow sensor's surface";
  type SourceRegion = enumeration(Box "Box (centre, half extents)", Disc "Disc or cylinder (centre, normal, radius, thickness)")
    "Region a particle source inserts into";
  type SizeDistribution = enumeration(Constant "Every particle rMin", Uniform "Uniform in [rMin, rMax]",
    Linear "pdf linear from weightAtMin at rMin to weightAtMax at rMax",
    Normal "Normal(mean, std) truncated to [rMin, rMax]",
    Discrete "One of discreteRadii with probability proportional to discreteWeights")
    "Radius distribution of inserted particles (the solver paper's distributions)";
  type BodyMotion = enumeration(Predicted "The body moves on with the sent velocity during the interval (docs/protocol.md)",
    Lagged "The body stays at the sent pose during the interval") "How the server moves a body between two exchanges";
  type ContactModel = enumeration(Default "The server's default (Hertz-Mindlin)", HertzMindlin "Hertz normal, Mindlin tangential",
    LinearSpringDashpot "Constant stiffness: cheaper") "Contact law of the DEM run (docs/physics.md)";
  type Integrator = enumeration(Default "The server's default (velocity Verlet)", VelocityVerlet "Second order, symplectic",
    ExplicitEuler "First order; for comparison only") "Time integrator of the DEM run";
  type Fidelity = enumeration(NoPreset "Each setting's own default", Draft "Quick looks: the largest step the limit accepts",
    Engineering "Design work: bulk quantities within a few per cent",
    Validation "Comparisons with experiments: restitution within 1 %")
    "Speed/accuracy preset for the settings left at their default (docs/accuracy.md)";
  type PointStyle = enumeration(Splat "Thin disc facing the view point (cheapest)",
    Diamond "Thin square turned 45 degrees, facing the view point", Sphere "Sphere (dearest)",
    Auto "By distance to the view point: spheres near, diamonds farther, splats far")
    "Shape DEMPoints draws for each particle";
end Types;
