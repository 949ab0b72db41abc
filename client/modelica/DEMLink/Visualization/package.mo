within DEMLink;
package Visualization "Particles in the tool's 3D view"
  extends Modelica.Icons.Package;
end Visualization;
