within;
/* Constructs of the Modelica concrete syntax (Appendix A of the specification) that the
   grammar must accept: /* is not nested */
encapsulated package SpecFeatures "Strings with escapes: \" \' \? \\ \a \b \f \n \r \t \v
and a line break" + " joined by +"
  import Modelica.Constants;
  import SI = Modelica.Units.SI;
  import Modelica.Math.*;
  import Modelica.Math.{sin, cos};
  import Modelica.Math.Matrices.* "wildcard with a dot and a star";

  type Vector3 = input Real[3](each unit = "m") "short class with base prefix, subscripts, modification";
  type Open = enumeration(:) "an open enumeration";
  type Choice = enumeration(First "first", Second "second" annotation (x = 1), Third);
  type Derivative = der(scale, x, y) "a derivative class";

  operator record Complex "an operator record"
    Real re;
    Real im;
    encapsulated operator '+' "a quoted operator name"
      function add
        input Complex a;
        input Complex b;
        output Complex c;
      algorithm
        c := Complex(re = a.re + b.re, im = a.im + b.im);
      end add;
    end '+';
  end Complex;

  expandable connector Bus "an expandable connector"
  end Bus;

  connector Pin
    Real v;
    flow Real i;
    stream Real h;
  end Pin;

  partial model Base
    replaceable package Medium = Open constrainedby Open "constraining clause" annotation (choicesAllMatching = true);
    replaceable Real r = 1 constrainedby Real;
    parameter Integer n(min = 1) = 3;
  end Base;

  model extends Base(n = 4) "an extends class specifier"
    'quoted ident\'s, with "quotes" and $ymbols: +-*/' q = 2;
  end Base;

  pure function scale "partial application target"
    input Real x;
    input Real k = 2.5e-3;
    output Real y;
  algorithm
    y := k * x;
    return;
  end scale;

  impure function sideEffect
    input Real x;
    output Real y;
    output Real z;
    external "C" y = c_side_effect(x, z) annotation (Include = "#include \"side.h\"", Library = {"side", "m"});
  end sideEffect;

  function defaultCall
    input Real x[:, :];
    output Real y;
    external;
  end defaultCall;

  function integrate
    input Real x;
    input Real f(x) = 0;
    output Real y = 0;
  end integrate;

  model Everything
    extends Base(redeclare package Medium = Open, final n = 5, redeclare replaceable Real r = 2);
    inner outer Pin pin if n > 1 "conditional, inner outer";
    Pin pins[n];
    discrete Real d(start = 0);
    constant Real c = 1.5E+3;
    parameter Real numbers[:] = {1, 2., 3.0e0, 4E-2, 0.5, 06};
    parameter Real matrix[2, 2] = [1, 2; 3, 4];
    Real x(start = 1, fixed = true), y, z[3];
    Real w[3] = {i ^ 2 for i in 1:3};
    Real s = sum(i * j for i in 1:3, j in {1, 2});
    Real p = -2 ^ 2 + 3 .* 4 ./ 5 .^ 2 .+ 1 .- 1;
    Boolean b = not x > 1 and (x <= 2 or x == 3) or x <> 4 and x >= 0 and x < 9;
    Real e = if b then 1 elseif x > 0 then 2 else if x < 0 then 3 else 4;
    Real last = z[end] + z[end - 1] + matrix[end, 1];
    Real applied = integrate(function scale(k = 3), 1);
    Real r2 = .5;
  initial equation
    x = 1;
  equation
    der(x) = -x;
    connect(pins[1], pins[2]) annotation (Line(points = {{0, 0}, {1, 1}}));
    if n > 2 then
      y = 1;
    elseif n > 1 then
      y = 2;
    else
      y = 3;
    end if;
    for i in 1:3, j loop
      z[i] = i;
    end for;
    when {initial(), sample(0, 1)} then
      reinit(x, 1);
    elsewhen x > 2 then
      assert(x < 3, "too large", AssertionLevel.warning);
    end when;
    pure(scale(1)) = scale(1) "a pure() call and a description";
  initial algorithm
    d := 0;
  algorithm
    (x, , y) := sideEffect(1);
    (, z[1]) := sideEffect(2);
    while d < 3 loop
      d := d + 1;
      if d > 10 then
        break;
      end if;
    end while;
    for k in 1:2 loop
      terminate("done") "a statement with a description";
    end for;
    when terminal() then
      d := .SpecFeatures.scale(1);
    end when;
  public
    Real afterPublic;
  protected
    Real hidden;
  end Everything;
  annotation (uses(Modelica(version = "4.0.0")), Documentation(info = "<html>Unicode in annotations: µ, ä</html>"));
end SpecFeatures;
