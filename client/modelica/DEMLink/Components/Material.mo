within DEMLink.Components;
model Material "A bulk material from the database or with custom values (negative: default)"
  outer DEMLink.Basics.SimulationBox simBox;
  parameter String name = "gravel" "Material name other components refer to";
  parameter String databaseName = "gravel" "Database material (sand, gravel, ...); empty: custom";
  parameter Real density = -1 "[kg/m3]; negative: default";
  parameter Real youngsModulus = -1 "[Pa]; negative: default";
  parameter Real poissonRatio = -1 "[-]; negative: default";
  parameter Real restitution = -1 "[-]; negative: default";
  parameter Real slidingFriction = -1 "[-]; negative: default";
  parameter Real rollingFriction = -1 "[-]; negative: default";
protected
  DEMLink.Functions.Client client = DEMLink.Functions.Client();
  parameter Integer handle(fixed = false);
initial algorithm
  DEMLink.Functions.check(client, DEMLink.Functions.connectToHost(client, simBox.address, simBox.port, name, simBox.token));
  handle := DEMLink.Functions.declareMaterial(client, name, databaseName, density, youngsModulus, poissonRatio,
    restitution, slidingFriction, rollingFriction);
algorithm
  when terminal() then
    DEMLink.Functions.check(client, DEMLink.Functions.finish(client, "terminal()"));
  end when;
end Material;
