/// The step's stage table: docs/architecture.md draws the same table as the code
/// (names, order, when each runs, which allow an owed half kick), and a scene runs
/// exactly the stages it needs.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "demlink/core/step/stage_table.hpp"
#include "test_scenes.hpp"

namespace demlink::core {
namespace {

struct DocRow {
  std::string name;
  bool pass = false;
  std::string runs_when;
  std::string kick_may_be_owed;  ///< "yes" or "no"
};

std::string trim(const std::string& text) {
  const auto begin = text.find_first_not_of(' ');
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(' ') - begin + 1);
}

/// Rows of the first Markdown table after the heading "## One time step".
std::vector<DocRow> docStageTable() {
  std::ifstream in(std::string(DEMLINK_SOURCE_DIR) + "/docs/architecture.md");
  EXPECT_TRUE(in.good()) << "cannot read docs/architecture.md";
  std::string line;
  while (std::getline(in, line) && line.rfind("## One time step", 0) != 0) {
  }
  while (std::getline(in, line) && line.rfind('|', 0) != 0) {
  }
  std::vector<DocRow> rows;
  bool header = true;
  for (; !line.empty() && line[0] == '|'; std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream cellStream(line.substr(1));
    for (std::string cell; std::getline(cellStream, cell, '|');) cells.push_back(trim(cell));
    if (header || line.rfind("|---", 0) == 0) {
      header = false;
      continue;
    }
    if (cells.size() < 6) {
      ADD_FAILURE() << "row with " << cells.size() << " cells: " << line;
      continue;
    }
    DocRow row;
    std::string name = cells[0];
    const std::string arrow = "↳ ";
    if (name.rfind(arrow, 0) == 0) {
      row.pass = true;
      name = name.substr(arrow.size());
    }
    std::erase(name, '`');
    row.name = name;
    row.runs_when = cells[4];
    row.kick_may_be_owed = cells[5];
    rows.push_back(row);
  }
  return rows;
}

TEST(StageTable, ArchitectureDocDrawsTheCodesTable) {
  const std::vector<DocRow> doc = docStageTable();
  const auto& table = stageTable();
  ASSERT_EQ(doc.size(), table.size()) << "docs/architecture.md \"One time step\" should be:\n"
                                      << stageTableMarkdown();
  for (std::size_t k = 0; k < table.size(); ++k) {
    EXPECT_EQ(doc[k].name, table[k].name) << "row " << k;
    EXPECT_EQ(doc[k].pass, table[k].pass) << "row " << k << " (" << table[k].name << ")";
    EXPECT_EQ(doc[k].runs_when, table[k].runs_when) << "row " << k << " (" << table[k].name << ")";
    EXPECT_EQ(doc[k].kick_may_be_owed, table[k].kick_may_be_owed ? "yes" : "no")
        << "row " << k << " (" << table[k].name << ")";
  }
  if (HasFailure()) ADD_FAILURE() << "docs/architecture.md \"One time step\" should be:\n" << stageTableMarkdown();
}

TEST(StageTable, NamesAreUniqueAndPassesFollowTheForceStage) {
  const auto& table = stageTable();
  for (std::size_t a = 0; a < table.size(); ++a) {
    for (std::size_t b = a + 1; b < table.size(); ++b) EXPECT_NE(table[a].name, table[b].name);
    if (table[a].pass) {
      ASSERT_GT(a, 0u);
      EXPECT_TRUE(table[a - 1].pass || table[a - 1].stage == Stage::kForces) << table[a].name;
    }
  }
}

/// A component that only says which stages it runs in.
class StageProbe final : public WorldComponent {
 public:
  StageProbe(std::string name, StageSet stages) : WorldComponent(std::move(name)), stages_(stages) {}
  [[nodiscard]] std::string_view kind() const override { return "probe"; }
  [[nodiscard]] StageSet stages() const override { return stages_; }

 private:
  StageSet stages_;
};

void addSphere(World& world, const Vec3& position) {
  ParticleSpec s;
  s.radius = 0.005;
  s.position = position;
  world.addParticle(s);
}

TEST(StageTable, SpheresAloneRunTheMinimalVerletStep) {
  World world(test::fineSettings(1.0e-5, 1.0));
  world.addMaterial(test::testMaterial(0.5));
  addSphere(world, Vec3::Zero());
  const std::vector<std::string> expected{"velocity_verlet", "neighbour_list", "forces",
                                          "particle_contacts:hertz_mindlin", "second_half_kick", "advance_clock",
                                          "watchdog"};
  EXPECT_EQ(world.activeStages(), expected);
  world.initialize();
  world.step();
  EXPECT_EQ(world.activeStages(), expected);
}

TEST(StageTable, EulerRunsNoSecondKickAndPlanesAndBoundsAddTheirStages) {
  SimulationSettings settings = test::fineSettings(1.0e-5, 1.0, ContactModel::LinearSpringDashpot);
  settings.integrator = IntegratorKind::ExplicitEuler;
  settings.bounds = DomainBounds{Vec3::Constant(-1.0), Vec3::Constant(1.0)};
  World world(settings);
  const auto material = world.addMaterial(test::testMaterial(0.5));
  world.addPlane({"floor", Vec3(0.0, 0.0, -0.01), Vec3::UnitZ(), material});
  addSphere(world, Vec3::Zero());
  EXPECT_EQ(world.activeStages(),
            (std::vector<std::string>{"bounds_removal", "explicit_euler", "neighbour_list", "forces",
                                      "particle_contacts:linear_spring_dashpot", "plane_contacts", "advance_clock",
                                      "watchdog"}));
}

TEST(StageTable, EveryFeatureAddsItsStagesInStepOrder) {
  SimulationSettings settings = test::fineSettings(1.0e-5, 1.0);
  DomainBounds bounds{Vec3::Constant(-0.1), Vec3::Constant(0.1)};
  bounds.growing = true;
  bounds.limit_lower = Vec3::Constant(-1.0);
  bounds.limit_upper = Vec3::Constant(1.0);
  settings.bounds = bounds;
  settings.frame.linear_acceleration = Vec3(1.0, 0.0, 0.0);  // translating: clumps are allowed
  World world(settings);
  const auto material = world.addMaterial(test::testMaterial(0.5, 0.3, 0.1));
  const TriangleMesh floor = rectangleMesh(Vec3(0.0, 0.0, -0.02), 0.05, 0.05, 1, 1);
  world.addMesh(MeshBody("floor", floor.vertices, floor.triangles, material));
  ClumpSpec clump;
  clump.template_index = world.addClumpTemplate(
      ClumpTemplate("pair", {{Vec3(-0.002, 0.0, 0.0), 0.002}, {Vec3(0.002, 0.0, 0.0), 0.002}}));
  clump.material = material;
  world.addClump(clump);
  world.addComponent(std::make_unique<StageProbe>("feed", stageBit(Stage::kInsertRemove)));
  world.addComponent(std::make_unique<StageProbe>("drain", stageBit(Stage::kInsertRemove) | stageBit(Stage::kObserve)));
  world.addComponent(std::make_unique<StageProbe>("sensor", stageBit(Stage::kObserve)));
  const std::vector<std::string> expected{
      "mesh_motion",      "probe:feed",         "probe:drain",     "growing_bounds", "velocity_verlet",
      "moving_frame",     "clump_rigid_bodies", "neighbour_list",  "forces",         "particle_contacts:hertz_mindlin",
      "mesh_contacts",    "rolling_resistance", "clump_force_sum", "second_half_kick", "clump_half_kick",
      "advance_clock",    "probe:drain",        "probe:sensor",    "watchdog"};
  world.initialize();  // mixes the pairs: only now is rolling friction known
  EXPECT_EQ(world.activeStages(), expected);
  world.step();
  EXPECT_EQ(world.activeStages(), expected);
  world.setFrameMotion({});  // inertial again: the frame stage goes
  std::vector<std::string> inertial = expected;
  std::erase(inertial, "moving_frame");
  EXPECT_EQ(world.activeStages(), inertial);
}

}  // namespace
}  // namespace demlink::core
