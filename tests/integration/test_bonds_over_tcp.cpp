/// Parallel bonds declared by the C++ client over TCP with the real co-simulation host:
/// three spheres in a row bonded by a ParallelBonds component; region sensors count the
/// bonds by their midpoint (intact, then broken as the outer spheres fly apart), and a
/// bad field is refused naming it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "integration_support.hpp"

namespace demlink::integration {
namespace {

constexpr double kDt = 1.0e-5;        // [s]
constexpr double kRadius = 0.005;     // [m]
constexpr double kSpacing = 0.01001;  // centre distance: a 10 um gap [m]
constexpr int kSteps = 10;            // steps per exchange

std::filesystem::path freshRoot(const std::string& name) {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("demlink_e2e_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  return root;
}

/// Box, material and the three spheres (the outer two moving apart at `speed`).
void addRow(client::Session& s, double speed) {
  auto& box = s.add<client::SimulationBox>("box");
  box.setTimeStep(kDt).setInitialGravity({0.0, 0.0, 0.0});
  box.setRestitutionTolerance(0.2);
  box.setCommunicationInterval(kSteps * kDt);
  s.add<client::Material>("rock").setDensity(2500.0).setYoungsModulus(5e6);
  const char* const names[] = {"s0", "s1", "s2"};
  for (int i = 0; i < 3; ++i) {
    s.add<client::SingleParticle>(names[i])
        .setMaterial("rock")
        .setPosition({kSpacing * (i - 1), 0.0, 0.0})
        .setVelocity({speed * (i - 1), 0.0, 0.0})
        .setDiameter(2.0 * kRadius);
  }
}

TEST(BondsOverTcp, DeclaredByTheClientTheyAreMadeCountedAndBroken) {
  const std::filesystem::path root = freshRoot("bonds");
  InProcessServer server(hostOptions(root));
  client::Connection connection;
  connect(connection, server.port(), "bonds");
  client::Session s(connection);
  // Pulled at 2 mm/s a side, a bond reaches sigma_t / kn = 1e-6 m of stretch after about
  // 0.5 ms (5 exchanges); it then stores 4e-10 J, less than the outer sphere's 2.6e-9 J.
  addRow(s, 2.0e-3);
  s.add<client::ParallelBonds>("cement")
      .setStiffnessPerArea(1.0e7, 1.0e7)
      .setStrength(10.0, 1.0e6)
      .setGapTolerance(2.0e-5)
      .addMaterial("rock");
  auto& all = s.add<client::RegionSensor>("all");
  all.setBox({0.0, 0.0, 0.0}, {0.1, 0.1, 0.1}).setCommunicationInterval(kSteps * kDt);
  // Around the midpoint of s0-s1 only, holding no sphere centre.
  auto& left = s.add<client::RegionSensor>("left");
  left.setSphere({-0.5 * kSpacing, 0.0, 0.0}, 0.25 * kSpacing).setCommunicationInterval(kSteps * kDt);
  s.declarationsDone();
  ASSERT_NO_THROW(s.waitCompiled());

  ASSERT_TRUE(s.exchange());
  EXPECT_EQ(all.bondsIntact(), 2u) << "the two neighbouring pairs are bonded";
  EXPECT_EQ(all.bondsBroken(), 0u);
  EXPECT_EQ(left.count(), 0u);
  EXPECT_EQ(left.bondsIntact(), 1u) << "counted by its midpoint";
  std::uint64_t previousIntact = all.bondsIntact();
  int exchanges = 0;
  for (; exchanges < 200 && all.bondsBroken() < 2; ++exchanges) {
    ASSERT_TRUE(s.exchange());
    EXPECT_EQ(all.bondsIntact() + all.bondsBroken(), 2u);
    EXPECT_LE(all.bondsIntact(), previousIntact) << "a broken bond stays broken";
    EXPECT_EQ(left.bondsIntact() + left.bondsBroken(), 1u);
    previousIntact = all.bondsIntact();
  }
  EXPECT_EQ(all.bondsBroken(), 2u) << "both bonds break as the outer spheres fly apart";
  EXPECT_GT(exchanges, 2) << "the bonds held for a few intervals first";
  EXPECT_EQ(left.bondsBroken(), 1u);
  EXPECT_EQ(s.finish("done").reason(), "said Bye");
  server.stop();
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(root);
}

TEST(BondsOverTcp, ABadFieldIsRefusedNamingIt) {
  const std::filesystem::path root = freshRoot("bonds_refused");
  InProcessServer server(hostOptions(root));
  client::Connection connection;
  connect(connection, server.port(), "bonds_refused");
  client::Session s(connection);
  addRow(s, 0.0);
  s.add<client::ParallelBonds>("cement").setStiffnessPerArea(1.0e9, 1.0e9).setStrength(-5.0, 1.0e6);
  s.declarationsDone();
  try {
    (void)s.waitCompiled();
    ADD_FAILURE() << "expected the tensile strength to be refused";
  } catch (const client::ServerError& e) {
    EXPECT_EQ(e.code(), v1::Error::INVALID_DECLARATION) << e.what();
    EXPECT_EQ(e.field(), "cement.parallel_bonds.tensile_strength") << e.what();
    EXPECT_NE(std::string(e.what()).find("= -5"), std::string::npos) << e.what();
  }
  server.stop();
  if (!::testing::Test::HasFailure()) std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace demlink::integration
