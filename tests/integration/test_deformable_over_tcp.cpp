/// A deformable body over TCP: a client declares a sheet hung by four corners that it drives
/// with a pose (held where the sheet was built), reads back the reaction at the driven
/// corners, equal to the sheet's weight once it hangs at rest (static equilibrium:
/// sum of reactions = m g, within 1 %), then overloads it (gravity x 100 through the
/// SimulationBox input) and sees springs break.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "demlink/core/deformable/tet_mesh.hpp"
#include "integration_support.hpp"

namespace demlink::integration {
namespace {

constexpr double kDt = 1e-4;        // [s]
constexpr double kMass = 10.0;      // [kg]
constexpr double kG = 9.81;         // [m/s^2]
constexpr double kInterval = 0.01;  // [s]

TEST(DeformableOverTcp, DrivenCornersCarryTheWeightThenSpringsBreakUnderOverload) {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("demlink_e2e_deformable_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root);
  InProcessServer server(hostOptions(root));

  client::Connection connection;
  connect(connection, server.port(), "sheet model");
  client::Session session(connection);
  auto& box = session.add<client::SimulationBox>("box");
  box.setTimeStep(kDt).setEndTime(0.0).setInitialGravity({0.0, 0.0, -kG}).setExpectedCount(3);
  box.setCommunicationInterval(kInterval);
  session.add<client::Material>("steel").setDensity(7800.0).setYoungsModulus(2e8);
  auto& sheet = session.add<client::MassSpringBody>("sheet");
  // 5 x 5 nodes over 0.4 x 0.4 m; the four corners are driven, the reference is the centre.
  sheet.setBox({0.0, 0.0, -0.01}, {0.4, 0.4, 0.01}, 0.1).setMaterial("steel").setSprings(kMass, 1e4, 300.0);
  sheet.message().set_shear_factor(1.0);
  sheet.message().set_break_force(1000.0);
  for (const double x : {0.0, 0.4}) {
    for (const double y : {0.0, 0.4}) sheet.addDrivenRegion({x - 0.01, y - 0.01, -0.01}, {x + 0.01, y + 0.01, 0.01});
  }
  const client::Vec3 centre{0.2, 0.2, 0.0};
  sheet.setDrivenReference(centre).setOutputNodes({12});
  sheet.setCommunicationInterval(kInterval);
  session.declare();
  session.waitCompiled();
  EXPECT_NE(session.report().text().find("deformable sheet (mass_spring): 25 nodes"), std::string::npos)
      << session.report().text();

  // 4 s: the sheet sags and comes to rest (kinetic energy below 1e-5 J by then).
  while (box.time() < 4.0 - 0.5 * kInterval) {
    sheet.setDrivenPose(centre, {});
    ASSERT_TRUE(session.exchange());
  }
  const client::Vec3 reaction = sheet.drivenForce();
  EXPECT_NEAR(reaction.z, kMass * kG, 0.01 * kMass * kG) << "the driven corners carry the weight";
  EXPECT_NEAR(reaction.x, 0.0, 1e-3 * kMass * kG);
  EXPECT_NEAR(reaction.y, 0.0, 1e-3 * kMass * kG);
  EXPECT_LT(sheet.displacement(0).z, -1e-3) << "the centre node sags";
  EXPECT_EQ(sheet.brokenSprings(), 0u);

  box.setGravity({0.0, 0.0, -100.0 * kG});
  for (int k = 0; k < 50 && sheet.brokenSprings() == 0; ++k) {
    sheet.setDrivenPose(centre, {});
    ASSERT_TRUE(session.exchange());
  }
  EXPECT_GT(sheet.brokenSprings(), 0u) << "a 100 g load tears the corner springs";
  session.finish("test over");
  connection.close();
  server.stop();
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(root);
}

// An FEM beam (client::FemBody) whose end x = 0 a client drives with a pose held where the
// beam was built: once the beam rests (Rayleigh beta damps it within a second), the reaction at
// the driven end is the beam's weight (0.5 kg, within 1 %) and nothing is fixed.
TEST(DeformableOverTcp, DrivenEndOfAnFemBeamCarriesItsWeight) {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("demlink_e2e_fem_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root / "data");
  core::writeGmsh((root / "data" / "beam.msh").string(),
                  core::boxTetMesh(core::Vec3::Zero(), core::Vec3(0.2, 0.05, 0.05), 8, 2, 2, 1), "4.1");
  const double weight = 1000.0 * 0.2 * 0.05 * 0.05 * kG;
  server::CosimOptions options = hostOptions(root / "out");
  options.data_root = root / "data";
  InProcessServer server(options);

  client::Connection connection;
  connect(connection, server.port(), "beam model");
  client::Session session(connection);
  auto& box = session.add<client::SimulationBox>("box");
  box.setTimeStep(kDt).setEndTime(0.0).setInitialGravity({0.0, 0.0, -kG}).setExpectedCount(3);
  box.setCommunicationInterval(kInterval);
  session.add<client::Material>("steel").setDensity(7800.0).setYoungsModulus(2e8);
  auto& beam = session.add<client::FemBody>("beam");
  beam.setMesh("beam.msh", 1e8, 0.3, 1000.0).setRayleigh(1e-5, 200.0).setMaterial("steel");
  const client::Vec3 end{0.0, 0.025, 0.025};
  beam.addDrivenRegion({-1e-6, -1.0, -1.0}, {1e-6, 1.0, 1.0}).setDrivenReference(end);
  beam.setCommunicationInterval(kInterval);
  session.declare();
  session.waitCompiled();
  EXPECT_NE(session.report().text().find("deformable beam (fem)"), std::string::npos) << session.report().text();
  while (box.time() < 1.0 - 0.5 * kInterval) {
    beam.setDrivenPose(end, {});
    ASSERT_TRUE(session.exchange());
  }
  EXPECT_NEAR(beam.drivenForce().z / weight, 1.0, 0.01);
  EXPECT_LT(std::abs(beam.drivenForce().x), 1e-3 * weight);
  EXPECT_EQ(beam.fixedForce().z, 0.0);
  double lowest = 0.0;
  for (const client::Vec3& d : beam.displacements()) lowest = std::min(lowest, d.z);
  EXPECT_LT(lowest, -1e-6) << "the free end sags";
  EXPECT_EQ(beam.brokenSprings(), 0u);
  session.finish("test over");
  connection.close();
  server.stop();
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace demlink::integration
