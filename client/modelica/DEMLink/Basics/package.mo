within DEMLink;
package Basics "Simulation-wide settings"
  extends Modelica.Icons.Package;
end Basics;
