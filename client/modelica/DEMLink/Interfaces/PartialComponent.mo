within DEMLink.Interfaces;
partial model PartialComponent "Connection, declaration and Bye of one DEMLink component"
  outer DEMLink.Basics.SimulationBox simBox "The model's inner SimulationBox";
  parameter String name "Unique component name on the server";
  parameter Modelica.Units.SI.Time tc = simBox.tc "Communication interval (exchanged components)";
  // Set (final) by each component: its declaration in the generic layout (docs/c_abi.md).
  parameter String kind "Component kind" annotation (Dialog(tab = "Declaration", enable = false));
  parameter Boolean exchanged "True: exchanged every tc; false: declared only"
    annotation (Dialog(tab = "Declaration", enable = false));
  parameter Integer declInts[:] "Declare package ints" annotation (Dialog(tab = "Declaration", enable = false));
  parameter Real declReals[:] "Declare package reals from index 1"
    annotation (__DEMLink(mixedUnits = true), Dialog(tab = "Declaration", enable = false));
  parameter String declStrings[:] "Declare package strings from index 2"
    annotation (Dialog(tab = "Declaration", enable = false));
protected
  DEMLink.Functions.Client client = DEMLink.Functions.Client(simBox.address, simBox.port, name, simBox.token,
    simBox.timeout) "This component's connection (handle 0 on it), connected by its constructor";
initial algorithm
  // Declare and say so; no wait for Compiled here: it would block before the other
  // components have declared (they run one after the other in this thread).
  DEMLink.Functions.connectClient(client, simBox.address, simBox.port, name, simBox.token, simBox.timeout);
  DEMLink.Functions.declare(client, kind, name, if exchanged then tc else 0, declInts, declReals, declStrings);
  DEMLink.Functions.declarationsDone(client);
algorithm
  when terminal() then
    DEMLink.Functions.finish(client);
  end when;
  annotation (Icon(graphics = {Rectangle(extent = {{-100, 100}, {100, -100}}, lineColor = {95, 75, 45},
    fillColor = {235, 220, 190}, fillPattern = FillPattern.Solid), Text(extent = {{-150, 140}, {150, 105}},
    textString = "%name", textColor = {0, 0, 255})}), Documentation(info = "<html>
<p>Every component's own client connects when the tool constructs it (before any initial
algorithm runs); the initial algorithm declares the component in the generic layout of the
C ABI and ends with DeclarationsDone, so the server compiles when the last component's
initialisation ends; exchanged components send their inputs at
<code>sample(0, tc)</code> and, in the event iteration after every component has sent,
receive the interval that starts at that sample: the outputs at t are those of
[t, t + tc], as the C++ client's exchange() gives them; <code>terminal()</code> says Bye. The DEM run ends when
every component said Bye.</p></html>"));
end PartialComponent;
