within DEMLink;
package Examples "The coupling paper's use cases (section 6), small enough to run in minutes"
  extends Modelica.Icons.ExamplesPackage;
end Examples;
