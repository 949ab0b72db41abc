// FEM input files: Gmsh .msh (files written by Gmsh itself and by writeGmsh), Matrix Market,
// node and triangle lists; every error names the file, the line and the reason, never the
// file's content, and a header announcing more entries than the file can hold is refused.
#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include "deformable/fem_test_support.hpp"
#include "demlink/core/deformable/fem_assembly.hpp"
#include "demlink/core/deformable/fem_input_files.hpp"
#include "demlink/core/deformable/gmsh_reader.hpp"
#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

using fem_test::TempDir;

const std::string kData = std::string(DEMLINK_SOURCE_DIR) + "/tests/core/deformable/data/";

double tetVolume(const TetMesh& mesh, std::size_t e) {
  const std::uint32_t* t = &mesh.tets[e * mesh.nodesPerTet()];
  const Vec3& x0 = mesh.nodes[t[0]];
  return (mesh.nodes[t[1]] - x0).cross(mesh.nodes[t[2]] - x0).dot(mesh.nodes[t[3]] - x0) / 6.0;
}

/// Closed and outward: every directed edge appears once and its reverse once; the divergence
/// theorem's sum of (x . n) area / 3 over the triangles is the volume.
void expectClosedOutward(const std::vector<Vec3>& nodes,
                         const std::vector<std::array<std::uint32_t, 3>>& tris, double volume) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  double enclosed = 0.0;
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k)
      ++edges[{t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)]}];
    enclosed += nodes[t[0]].dot((nodes[t[1]] - nodes[t[0]]).cross(nodes[t[2]] - nodes[t[0]])) / 6.0;
  }
  for (const auto& [e, count] : edges) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
  EXPECT_NEAR(enclosed, volume, 1e-9 * volume);
}

// Files written by Gmsh 4.x (bar.geo): 4.1 with 10-node, 2.2 with 4-node tetrahedra.
TEST(FemReaders, ReadsGmshWrittenFiles) {
  const double volume = 0.1 * 0.02 * 0.02;
  for (const auto& [file, order] : {std::pair{"bar_order2.msh", 2}, std::pair{"bar_order1.msh", 1}}) {
    SCOPED_TRACE(file);
    const TetMesh mesh = readGmsh(kData + file);
    EXPECT_EQ(mesh.order, order);
    EXPECT_FALSE(mesh.faces.empty());
    double sum = 0.0;
    for (std::size_t e = 0; e < mesh.tetCount(); ++e) {
      ASSERT_GT(tetVolume(mesh, e), 0.0);
      sum += tetVolume(mesh, e);
      if (order == 2) {  // straight edges: mid-edge nodes in VTK order sit at the edge midpoints
        const std::uint32_t* t = &mesh.tets[e * 10];
        constexpr int kEdge[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};
        for (int m = 0; m < 6; ++m) {
          const Vec3 mid = 0.5 * (mesh.nodes[t[kEdge[m][0]]] + mesh.nodes[t[kEdge[m][1]]]);
          ASSERT_LT((mesh.nodes[t[4 + m]] - mid).norm(), 1e-12) << "element " << e << " node " << 4 + m;
        }
      }
    }
    EXPECT_NEAR(sum, volume, 1e-12);
    expectClosedOutward(mesh.nodes, surfaceTriangles(mesh), volume);
    const FemMatrices m = assembleTetMesh(mesh, {1e9, 0.3, 2000.0}, true);
    EXPECT_NEAR(m.mass.sum(), 3.0 * 2000.0 * volume, 1e-9);
  }
}

// writeGmsh -> readGmsh gives the same mesh in both formats; inward file triangles are turned
// outward; without file triangles the boundary is extracted.
TEST(FemReaders, GmshRoundTripAndSurfaceOrientation) {
  TempDir dir("readers");
  for (const int order : {1, 2}) {
    TetMesh mesh = boxTetMesh(Vec3::Zero(), Vec3(0.3, 0.1, 0.2), 3, 2, 2, order);
    const std::vector<std::uint32_t> outward = boundaryFaces(mesh);
    expectClosedOutward(mesh.nodes, surfaceTriangles(mesh), 0.3 * 0.1 * 0.2);
    mesh.faces = outward;
    const std::size_t npf = mesh.nodesPerFace();
    for (std::size_t f = 0; f < mesh.faces.size(); f += 2 * npf) {  // every other face turned inward
      std::swap(mesh.faces[f + 1], mesh.faces[f + 2]);
      if (npf == 6) std::swap(mesh.faces[f + 3], mesh.faces[f + 5]);
    }
    for (const std::string version : {"2.2", "4.1"}) {
      const std::string path = dir.file("box" + version + ".msh");
      writeGmsh(path, mesh, version);
      const TetMesh back = readGmsh(path);
      EXPECT_EQ(back.order, order);
      EXPECT_EQ(back.nodes, mesh.nodes);
      EXPECT_EQ(back.tets, mesh.tets);
      EXPECT_EQ(back.faces, mesh.faces);
      expectClosedOutward(back.nodes, surfaceTriangles(back), 0.3 * 0.1 * 0.2);
    }
  }
}

/// The InputError `parse` throws; fails the test if none.
template <class Parse>
InputError errorOf(Parse&& parse) {
  try {
    parse();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError("", "", "");
}

void expectLineError(const InputError& e, const std::string& prefix, int line,
                     const std::string& reasonPart) {
  EXPECT_EQ(e.field(), prefix + ":line " + std::to_string(line)) << e.what();
  EXPECT_NE(e.reason().find(reasonPart), std::string::npos) << e.what();
  EXPECT_EQ(std::string(e.what()).find("SECRET"), std::string::npos) << "echoes file content: " << e.what();
}

TEST(FemReaders, GmshErrorsNameFileAndLine) {
  const std::string head = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  const std::string nodes = "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n";
  expectLineError(errorOf([&] { (void)parseGmsh(head + "$Nodes\n1\n1 0 SECRET 0\n$EndNodes\n", "a.msh"); }),
                  "msh:a.msh", 6, "not a number");
  expectLineError(errorOf([&] { (void)parseGmsh(head + "$Nodes\n1000000000000\n1 0 0 0\n", "a.msh"); }),
                  "msh:a.msh", 5, "announces 1000000000000 entries");
  expectLineError(errorOf([&] { (void)parseGmsh("$MeshFormat\n2.2 1 8\n$EndMeshFormat\n", "a.msh"); }),
                  "msh:a.msh", 2, "binary");
  expectLineError(errorOf([&] { (void)parseGmsh("$MeshFormat\n3.0 0 8\n$EndMeshFormat\n", "a.msh"); }),
                  "msh:a.msh", 2, "unsupported .msh version");
  expectLineError(errorOf([&] {
                    (void)parseGmsh(head + nodes + "$Elements\n1\n1 5 0 1 2 3 4 1 2 3 4\n$EndElements\n",
                                    "a.msh");
                  }),
                  "msh:a.msh", 13, "unsupported element type 5");
  expectLineError(errorOf([&] {
                    (void)parseGmsh(head + nodes + "$Elements\n1\n1 4 0 1 2 3 9\n$EndElements\n", "a.msh");
                  }),
                  "msh:a.msh", 13, "node tag 9");
  expectLineError(errorOf([&] {
                    (void)parseGmsh(head + nodes + "$Elements\n1\n1 4 0 1 2 3 3\n$EndElements\n", "a.msh");
                  }),
                  "msh:a.msh", 13, "flat tetrahedron");
  expectLineError(errorOf([&] { (void)parseGmsh(head + nodes + "$Elements\n2\n1 4 0 1 2 3 4\n", "a.msh"); }),
                  "msh:a.msh", 12, "announces 2 entries");
  const InputError none =
      errorOf([&] { (void)parseGmsh(head + nodes + "$Elements\n0\n$EndElements\n", "a.msh"); });
  EXPECT_EQ(none.field(), "msh:a.msh");
  const InputError missing = errorOf([&] { (void)readGmsh("/nonexistent/x.msh"); });
  EXPECT_EQ(missing.field(), "msh:/nonexistent/x.msh");
  EXPECT_EQ(missing.reason(), "no such file");
  // The good file parses.
  EXPECT_EQ(parseGmsh(head + nodes + "$Elements\n1\n1 4 2 0 1 1 2 3 4\n$EndElements\n", "a.msh").tetCount(),
            1u);
}

TEST(FemReaders, MatrixMarketReadsAndRejects) {
  const Eigen::SparseMatrix<double> g = parseMatrixMarket(
      "%%MatrixMarket matrix coordinate real general\n% c\n2 2 3\n1 1 2.5\n2 1 -1\n2 2 4\n", "m.mtx");
  EXPECT_EQ(g.coeff(0, 0), 2.5);
  EXPECT_EQ(g.coeff(1, 0), -1.0);
  EXPECT_EQ(g.coeff(0, 1), 0.0);
  const Eigen::SparseMatrix<double> s = parseMatrixMarket(
      "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 2.5\n2 1 -1\n2 2 4\n", "m.mtx");
  EXPECT_EQ(s.coeff(0, 1), -1.0);
  EXPECT_EQ(s.coeff(1, 0), -1.0);
  const std::string banner = "%%MatrixMarket matrix coordinate real symmetric\n";
  expectLineError(
      errorOf([&] { (void)parseMatrixMarket("%%MatrixMarket matrix array real general\n", "m.mtx"); }),
      "mtx:m.mtx", 1, "coordinate");
  expectLineError(errorOf([&] { (void)parseMatrixMarket(banner + "9 9 1000000000000\n1 1 1\n", "m.mtx"); }),
                  "mtx:m.mtx", 2, "announces 1000000000000 entries");
  expectLineError(errorOf([&] { (void)parseMatrixMarket(banner + "2 2 2\n1 1 1\n3 1 SECRET\n", "m.mtx"); }),
                  "mtx:m.mtx", 4, "not a number");
  expectLineError(errorOf([&] { (void)parseMatrixMarket(banner + "2 2 2\n1 1 1\n3 1 1\n", "m.mtx"); }),
                  "mtx:m.mtx", 4, "outside the matrix");
  expectLineError(errorOf([&] { (void)parseMatrixMarket(banner + "2 2 2\n1 1 1\n1 2 1\n", "m.mtx"); }),
                  "mtx:m.mtx", 4, "lower triangle");
  expectLineError(
      errorOf([&] { (void)parseMatrixMarket(banner + "200000000 200000000 1\n1 1 1\n", "m.mtx"); }),
      "mtx:m.mtx", 2, "dimension above the limit");
  const InputError truncated =
      errorOf([&] { (void)parseMatrixMarket(banner + "2 2 3\n1 1 1.0000\n2 2 1.0000\n", "m.mtx"); });
  EXPECT_EQ(truncated.field(), "mtx:m.mtx");
  EXPECT_NE(truncated.reason().find("announces 3 entries"), std::string::npos) << truncated.what();
}

TEST(FemReaders, NodeAndTriangleFiles) {
  const std::vector<Vec3> nodes = parseNodeFile("# x y z\n0 0 0\n\n1 0 0\n0 1 0.5\n", "n.txt");
  ASSERT_EQ(nodes.size(), 3u);
  EXPECT_EQ(nodes[2], Vec3(0, 1, 0.5));
  const auto tris = parseTriangleFile("# a b c\n0 1 2\n", "t.txt", 3);
  ASSERT_EQ(tris.size(), 1u);
  EXPECT_EQ(tris[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  expectLineError(errorOf([&] { (void)parseNodeFile("0 0 0\n1 SECRET 0\n", "n.txt"); }), "nodes:n.txt", 2,
                  "not a number");
  expectLineError(errorOf([&] { (void)parseNodeFile("0 0 0\n1 0\n", "n.txt"); }), "nodes:n.txt", 2,
                  "'x y z'");
  expectLineError(errorOf([&] { (void)parseTriangleFile("0 1 2\n\n0 1 3\n", "t.txt", 3); }),
                  "triangles:t.txt", 3, "out of range");
  expectLineError(errorOf([&] { (void)parseTriangleFile("0 1 1\n", "t.txt", 3); }), "triangles:t.txt", 1,
                  "repeats a node");
}

// FemBody names its own field and keeps the file's place in the reason.
TEST(FemReaders, BodyErrorsNameTheField) {
  TempDir dir("body_errors");
  {
    std::ofstream bad(dir.file("bad.msh"));
    bad << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 SECRET\n$EndNodes\n";
  }
  const fem_test::Beam beam = fem_test::Beam::coarse(4);
  FemSpec spec = beam.spec(dir.file("bad.msh"));
  const InputError e = errorOf([&] { FemBody(spec, 1e-4, "bodies[1]"); });
  EXPECT_EQ(e.field(), "bodies[1].mesh.msh_file");
  EXPECT_NE(e.reason().find(dir.file("bad.msh") + ":line 6"), std::string::npos) << e.what();
  EXPECT_EQ(std::string(e.what()).find("SECRET"), std::string::npos);

  writeGmsh(dir.file("beam.msh"), beam.mesh(), "4.1");
  spec = beam.spec(dir.file("beam.msh"));
  spec.poisson_ratio = 0.5;
  EXPECT_EQ(errorOf([&] { FemBody(spec, 1e-4, "b"); }).field(), "b.poisson_ratio");
  spec = beam.spec(dir.file("beam.msh"));
  spec.fixed_regions.push_back({Vec3(5, 5, 5), Vec3(6, 6, 6)});
  EXPECT_EQ(errorOf([&] { FemBody(spec, 1e-4, "b"); }).field(), "b.fixed.regions[1]");
  spec = beam.spec(dir.file("beam.msh"));
  spec.fixed_nodes = {1, 99999};
  EXPECT_EQ(errorOf([&] { FemBody(spec, 1e-4, "b"); }).field(), "b.fixed.nodes[1]");
  spec = beam.spec(dir.file("beam.msh"));
  spec.mass_matrix_path = "m.mtx";
  EXPECT_EQ(errorOf([&] { FemBody(spec, 1e-4, "b"); }).field(), "b.mesh.msh_file");
  spec = beam.spec(dir.file("beam.msh"));
  spec.integrator = FemIntegrator::kCentralDifference;
  spec.mass = FemMass::kConsistent;
  EXPECT_EQ(errorOf([&] { FemBody(spec, 1e-4, "b"); }).field(), "b.integrator");
  spec = beam.spec(dir.file("beam.msh"));
  FemBody body(spec, 1e-4, "b");
  EXPECT_EQ(errorOf([&] { body.beginStep(2e-4, Vec3::Zero()); }).field(), "b.time_step");
}

}  // namespace
}  // namespace demlink::core
