package DEMLink "Couple Modelica system models to the DEMLink DEM server over TCP"
  extends Modelica.Icons.Package;
  annotation (version = "0.2.0", versionDate = "2026-11-24", uses(Modelica(version = "4.0.0")),
    Documentation(info = "<html>
<p>The component library of the coupling paper (<i>A New Object-Oriented Approach for
Integrating Discrete Element Method into Modelica</i>) on the DEMLink server.</p>
<p>Every model needs exactly one <code>inner DEMLink.Basics.SimulationBox simBox</code>;
every component refers to it with <code>outer</code> (address, port, communication
interval). Each component owns one connection (an ExternalObject
<code>Functions.Client</code>): its <code>initial algorithm</code> connects and declares,
<code>when sample(0, tc)</code> sends its inputs and, in the event iteration after every
component has sent, receives the interval [t, t + tc] (no lag, docs/modelica.md) and
<code>when terminal()</code> says Bye; the DEM run ends with the model's run.</p>
<ul>
<li>Basics: SimulationBox</li>
<li>Components: Material, Plane, SingleParticle, ParticleSystem, ParticleSource,
ParticleSink, PitGenerator, ParallelBonds, RigidBody / RigidBodyFrame (box or STL on the server),
CADPart / CADPartFrame (STL from this computer); the *Frame variants connect to
Modelica.Mechanics.MultiBody</li>
<li>Sensors: RegionSensor, FlowSensor</li>
<li>Visualization: DEMPoints</li>
<li>Examples: BucketDigging, TruckLoading, SwitchedSourceAndSink (run-time inputs)</li>
</ul>
<p>The C functions are in libdemlink_c (Resources/Library/linux64, header in
Resources/Include, filled by the CMake target <code>demlink_modelica_resources</code>);
docs/modelica.md describes loading the package in OpenModelica and Dymola, and the
quaternion and sign conventions.</p></html>"));
end DEMLink;
