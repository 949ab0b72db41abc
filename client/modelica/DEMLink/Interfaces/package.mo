within DEMLink;
package Interfaces "Partial models shared by the components"
  extends Modelica.Icons.InterfacesPackage;
end Interfaces;
