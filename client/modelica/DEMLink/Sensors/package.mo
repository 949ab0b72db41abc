within DEMLink;
package Sensors "Particle count and mass in regions and through surfaces"
  extends Modelica.Icons.SensorsPackage;
end Sensors;
