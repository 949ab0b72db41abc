// A 0.1 x 0.02 x 0.02 m bar for the Gmsh reader tests (test_fem_readers.cpp). Regenerate with
//   gmsh -3 -order 2 -format msh41 bar.geo -o bar_order2.msh
//   gmsh -3 -format msh22 bar.geo -o bar_order1.msh
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.02, 0.02};
Mesh.CharacteristicLengthMax = 0.02;
