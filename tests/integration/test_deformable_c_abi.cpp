/// Deformable bodies through the C ABI (tests/client/deformable_sequence.c) against the real
/// demlink-server, both as child processes (child_process.hpp says why): a 10 kg mass-spring
/// sheet hung by its driven corners and an FEM beam clamped at one end, under gravity for
/// 8 s. Momentum balance: the mean reaction over the last 4 s (the sheet, without shear
/// springs, still swings; its momentum changes by less than 1 N s in that time) is the
/// weight, at the driven corners the sheet's, at the clamp the beam's, each within 1 %.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "child_process.hpp"
#include "demlink/core/deformable/tet_mesh.hpp"

namespace demlink::integration {
namespace {

TEST(DeformableCAbiRealServer, DrivenAndFixedReactionsCarryTheWeights) {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("demlink_e2e_deformable_c_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root / "data");
  // Beam 0.2 x 0.05 x 0.05 m of linear tetrahedra, 1000 kg/m^3: 0.5 kg.
  core::writeGmsh((root / "data" / "beam.msh").string(),
                  core::boxTetMesh(core::Vec3::Zero(), core::Vec3(0.2, 0.05, 0.05), 8, 2, 2, 1), "4.1");
  const double beamWeight = 1000.0 * 0.2 * 0.05 * 0.05 * 9.81;
  const double sheetWeight = 10.0 * 9.81;

  Child server({DEMLINK_SERVER_EXE, "--port", "0", "--once", "--output", (root / "out").string(), "--data-root",
                (root / "data").string()});
  const std::string announced = server.readLine(std::chrono::seconds(10));
  const auto [host, port] = announcedAddress(announced);
  ASSERT_GT(std::atoi(port.c_str()), 0) << announced;

  Child program({DEMLINK_DEFORMABLE_SEQUENCE_EXE, host, port, "beam.msh", "8"});
  const std::string line = program.readLine(std::chrono::seconds(120));
  EXPECT_EQ(program.waitForExit(std::chrono::seconds(30)), 0) << line;
  double sheet = 0.0;
  int nodes = 0;
  int broken = -1;
  double beam = 0.0;
  double beamX = 0.0;
  ASSERT_EQ(std::sscanf(line.c_str(), "sheet %lf nodes %d broken %d beam %lf %lf", &sheet, &nodes, &broken, &beam,
                        &beamX),
            5)
      << line;
  EXPECT_NEAR(sheet / sheetWeight, 1.0, 0.01) << line;
  EXPECT_NEAR(beam / beamWeight, 1.0, 0.01) << line;
  EXPECT_LT(std::abs(beamX), 1e-3 * beamWeight) << line;
  EXPECT_EQ(nodes, 25) << "every surface node of the sheet is reported";
  EXPECT_EQ(broken, 0);
  EXPECT_EQ(server.waitForExit(std::chrono::seconds(10)), 0) << "--once: the server exits after the simulation";
  std::printf("%s (sheet weight %.6g N, beam weight %.6g N)\n", line.c_str(), sheetWeight, beamWeight);
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace demlink::integration
