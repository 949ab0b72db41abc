within DEMLink;
package Components "DEM components of a system model: materials, walls, particles, bodies"
  extends Modelica.Icons.Package;
end Components;
