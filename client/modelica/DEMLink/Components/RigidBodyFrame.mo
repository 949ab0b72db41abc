within DEMLink.Components;
model RigidBodyFrame "A box or an STL mesh on the server, moved through a MultiBody frame; returns the particles' wrench"
  extends DEMLink.Interfaces.PartialFrameBody(name = "body", final geometry = if Modelica.Utilities.Strings.isEmpty(stlFile)
    then 1 else 0, final geometryText = stlFile);
  parameter String stlFile = "" "STL file on the SERVER (within its --data-root); empty: a box of boxSize";
end RigidBodyFrame;
