within;
package ValidLib "A small package the checker must pass: one of each construct it checks"
  extends Modelica.Icons.Package;

  class Handle "An ExternalObject around a C handle"
    extends ExternalObject;
    function constructor
      input String name;
      input Real timeout;
      output Handle handle;
      external "C" handle = vl_open(name, timeout) annotation (Library = "validlib", Include = "#include \"validlib.h\"");
    end constructor;

    function destructor
      input Handle handle;
      external "C" vl_close(handle) annotation (Library = "validlib", Include = "#include \"validlib.h\"");
    end destructor;
  end Handle;

  impure function exchange "Sends values, receives a status, counts and values"
    input Handle handle;
    input Real values[:];
    input Boolean enabled;
    input Units unitChoice;
    output Integer status;
    output Integer counts[2];
    output Real received[3];
    output String message;
    external "C" status = vl_exchange(handle, values, size(values, 1), enabled, unitChoice, counts, received, message)
      annotation (Library = "validlib", Include = "#include \"validlib.h\"");
  end exchange;

  function scale "The default external call: inputs, then the single scalar output as the result"
    input Real x;
    input Real factor = 2;
    output Real y;
    external "C" annotation (Include = "#include \"validlib.h\"");
  end scale;

  type Units = enumeration(SI "SI units", Other "Anything else") "A choice";
  type Ratio = Real(unit = "1") "A dimensionless ratio";

  model Part "A component with parameters of every kind the unit rule knows"
    parameter Modelica.Units.SI.Length length = 1 "An SI type";
    parameter Real rate(unit = "1/s") = 3 "A unit modifier";
    parameter Real direction[3](each unit = "1") = {0, 0, 1} "A dimensionless array";
    parameter Ratio share = 0.5 "A short class with a unit";
    parameter Real mixed[:] = {1, 2} "Values of several units" annotation (__DEMLink(mixedUnits = true));
    parameter Integer count = 2 "Integers have no unit";
    parameter Boolean flag = true;
    parameter String name = "part";
    parameter Units choice = Units.SI;
    parameter Modelica.Mechanics.MultiBody.Types.Color color = {255, 0, 0};
    Modelica.Blocks.Interfaces.RealInput u[3] "Signals in";
    Modelica.Blocks.Interfaces.RealOutput y "Signal out";
  protected
    Handle handle = Handle(name, 1.0);
    Integer status(start = 0, fixed = true);
    Integer counts[2];
    Real received[3];
    String message;
  algorithm
    when sample(0, 0.1) then
      (status, counts, received, message) := exchange(handle, u, flag, choice);
      y := scale(received[1], factor = share);
    end when;
  end Part;

  model Example "Connections of every checked kind"
    extends Modelica.Icons.Example;
    Part part(length = 2, rate(unit = "1/s") = 4);
    Modelica.Blocks.Sources.Constant source[3](k = {1, 2, 3});
    Modelica.Blocks.Sources.Step step;
    Modelica.Mechanics.MultiBody.Parts.Body body(m = 1);
    Modelica.Mechanics.MultiBody.Joints.Prismatic joint(useAxisFlange = true);
    Modelica.Mechanics.Translational.Components.SpringDamper spring(c = 1, d = 1);
  equation
    connect(source.y, part.u);
    connect(joint.frame_b, body.frame_a);
    connect(spring.flange_a, joint.support);
    connect(spring.flange_b, joint.axis);
  end Example;
  annotation (uses(Modelica(version = "4.0.0")));
end ValidLib;
