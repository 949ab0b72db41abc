within DEMLink.Components;
model CADPartFrame "A CAD part (STL file on the client, sent to the server), moved through a MultiBody frame; returns the particles' wrench"
  extends DEMLink.Interfaces.PartialFrameBody(name = "part", final geometry = 2,
    final geometryText = Modelica.Utilities.Files.loadResource(fileName));
  parameter String fileName = "modelica://DEMLink/Resources/Data/bucket.stl"
    "STL file (modelica:// URI or path on this computer); its bytes are sent to the server";
end CADPartFrame;
