within DEMLink;
package Components "DEM components of a system model"
  extends Modelica.Icons.Package;
end Components;
