within DEMLink.Components;
model RigidBody "A box or an STL mesh on the server, moved through plain signals; returns the particles' wrench"
  extends DEMLink.Interfaces.PartialSignalBody(name = "body", final geometry = if Modelica.Utilities.Strings.isEmpty(stlFile)
    then 1 else 0, final geometryText = stlFile);
  parameter String stlFile = "" "STL file on the SERVER (within its --data-root); empty: a box of boxSize";
end RigidBody;
