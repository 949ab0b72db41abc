package DEMLink "Couple Modelica system models to the DEMLink DEM server over TCP"
  extends Modelica.Icons.Package;
  annotation (Documentation(info="<html>
<p>Every model needs exactly one <code>inner DEMLink.Basics.SimulationBox simBox</code>;
every component refers to it with <code>outer</code> (address, port, communication interval).
Each component owns one connection (an ExternalObject <code>Functions.Client</code>):
its <code>initial algorithm</code> connects and declares, <code>when sample(0, tc)</code>
exchanges (receiving the outputs of the interval that just ended, then sending its
inputs for the next one) and <code>when terminal()</code> says Bye. The C functions are
in libdemlink_c (header demlink/demlink_c.h); docs/c_abi.md describes them.</p>
</html>"));
end DEMLink;
