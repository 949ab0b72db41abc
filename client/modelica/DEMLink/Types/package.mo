within DEMLink;
package Types "Choices of the DEMLink components"
  extends Modelica.Icons.TypesPackage;
  type RegionShape = enumeration(Box "Box (centre, size, orientation)", Sphere "Sphere (centre, radius)")
    "Shape of a region sensor or particle sink";
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
end Types;
