within DEMLink;
package Types "Choices of the DEMLink components"
  extends Modelica.Icons.TypesPackage;
  type RegionShape = enumeration(Box "Box (centre, size, orientation)", Sphere "Sphere (centre, radius)")
    "Shape of a region sensor or particle sink";
  type FlowShape = enumeration(Rectangle "Rectangle (centre, normal, length, width, length axis)", Disc "Disc (centre, normal, radius)")
    "Shape of a flow sensor's surface";
  type BodyMotion = enumeration(Predicted "The body moves on with the sent velocity during the interval (docs/protocol.md)",
    Lagged "The body stays at the sent pose during the interval") "How the server moves a body between two exchanges";
end Types;
