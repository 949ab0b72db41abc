// Co-simulation compiler: when it compiles (expected count, expected names, quiet period)
// and what it refuses, each refusal naming the component and the field.
#include <gtest/gtest.h>

#include "cosim_test_support.hpp"

namespace demlink::server::test {
namespace {

TEST(CosimCompile, ExpectedCountCompilesOnTheLastDeclaration) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  h.declare(1, boxJson(1e-5, 0.0, R"("coupling": {"expected_count": 3})", 2e-5));  // exchanged: the run can advance
  h.declare(1, smallBedJson()[0]);
  EXPECT_FALSE(h.host().simulationRunning());
  EXPECT_FALSE(h.compiled(1));
  h.declare(1, smallBedJson()[1]);
  ASSERT_TRUE(h.compiled(1));
  EXPECT_TRUE(h.host().simulationRunning());
  EXPECT_EQ(h.compiled(1)->all_components_size(), 3);
  EXPECT_EQ(h.compiled(1)->end_step(), 0u);  // end_time 0: until Bye
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "sim_001" / "compile_report.txt"));
}

TEST(CosimCompile, ExpectedNamesWaitForEveryName) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  h.hello(2);
  h.declare(1, boxJson(1e-5, 0.0, R"("coupling": {"expected_names": ["glass", "floor"]})", 2e-5));
  h.declare(2, smallBedJson()[1]);
  EXPECT_FALSE(h.host().simulationRunning());
  h.declare(1, smallBedJson()[0]);
  ASSERT_TRUE(h.compiled(1));
  ASSERT_TRUE(h.compiled(2));
  EXPECT_EQ(h.compiled(2)->components_size(), 1);  // only its own: floor
  EXPECT_EQ(h.compiled(2)->components(0).name(), "floor");
  EXPECT_TRUE(h.compiled(2)->components(0).remote());
}

TEST(CosimCompile, QuietPeriodCompilesViaPoll) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  h.declare(1, boxJson(1e-5, 0.0, "", 2e-5));
  h.declare(1, smallBedJson()[0]);
  h.advanceClock(1.5);
  h.poll();
  EXPECT_FALSE(h.compiled(1));
  h.declare(1, smallBedJson()[1]);  // restarts the quiet period
  h.advanceClock(1.5);
  h.poll();
  EXPECT_FALSE(h.compiled(1));
  ASSERT_TRUE(h.host().nextDeadline());
  EXPECT_EQ(*h.host().nextDeadline(), h.now() + std::chrono::milliseconds(500));
  h.advanceClock(0.6);
  h.poll();
  ASSERT_TRUE(h.compiled(1));
  EXPECT_EQ(h.compiled(1)->all_components_size(), 3);
}

TEST(CosimCompile, DeclareTimeRefusalsNameTheComponent) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  h.declare(1, boxJson(1e-5, 0.0));
  h.declare(1, R"({"name": "nothing"})");
  h.declare(1, smallBedJson()[0]);
  h.declare(1, smallBedJson()[0]);  // the same declaration again (a repeated initialisation): ignored
  h.declare(1, R"({"name": "glass", "material": {"density": 1234}})");  // same name, other content
  h.declare(1, R"({"name": "", "material": {}})");
  h.declare(1, R"({"name": "box2", "simulation_box": {}})");
  const std::vector<v1::Error> errors = h.errors(1);
  ASSERT_EQ(errors.size(), 4u);
  EXPECT_EQ(errors[0].code(), v1::Error::UNKNOWN_COMPONENT_KIND);
  EXPECT_EQ(errors[0].component(), "nothing");
  EXPECT_EQ(errors[1].code(), v1::Error::DUPLICATE_NAME);
  EXPECT_EQ(errors[1].component(), "glass");
  EXPECT_EQ(errors[2].code(), v1::Error::DUPLICATE_NAME);
  EXPECT_EQ(errors[3].code(), v1::Error::INVALID_DECLARATION);
  EXPECT_EQ(errors[3].component(), "box2");
  for (const v1::Error& e : errors) EXPECT_FALSE(e.fatal());
  EXPECT_FALSE(h.closed(1));
}

/// Compiles `components` (declared by one client, then the quiet period) and returns the
/// Error the client got.
v1::Error compileError(const std::vector<std::string>& components) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  for (const std::string& c : components) h.declare(1, c);
  h.advanceClock(3.0);
  h.poll();
  const std::vector<v1::Error> errors = h.errors(1);
  EXPECT_FALSE(h.host().simulationRunning());
  EXPECT_EQ(h.host().simulationsFinished(), 1u);
  EXPECT_TRUE(h.finished(1));
  if (errors.size() != 1) {
    ADD_FAILURE() << "expected one error, got " << errors.size();
    return {};
  }
  EXPECT_EQ(errors[0].code(), v1::Error::INVALID_DECLARATION);
  EXPECT_TRUE(errors[0].fatal());
  return errors[0];
}

TEST(CosimCompile, CompileErrorsNameComponentAndField) {
  const std::string glass = smallBedJson()[0];
  {
    const v1::Error e = compileError({glass});
    EXPECT_EQ(e.field(), "simulation_box");
  }
  {
    const v1::Error e = compileError({boxJson(1e-5, 0.0), R"({"name": "floor", "plane": {"normal": {"z": 1}, "material": "stel"}})"});
    EXPECT_EQ(e.component(), "floor");
    EXPECT_EQ(e.field(), "floor.plane.material");
    EXPECT_NE(e.message().find("stel"), std::string::npos);
  }
  {
    const v1::Error e = compileError({boxJson(1e-5, 0.0), glass,
                                      R"({"name": "fill", "communication_interval": 0.001, "region_sensor": {"region": {"sphere": {"radius": 0.1}, "attached_to": "bucket"}}})"});
    EXPECT_EQ(e.component(), "fill");
    EXPECT_EQ(e.field(), "fill.region_sensor.region.attached_to");
  }
  {
    const v1::Error e = compileError({boxJson(1e-5, 0.0, R"("coupling": {"strict_intervals": true})"), glass,
                                      R"({"name": "view", "communication_interval": 0.000125, "particle_view": {}})"});
    EXPECT_EQ(e.component(), "view");
    EXPECT_EQ(e.field(), "view.communication_interval");
    EXPECT_NE(e.message().find("0.000125"), std::string::npos);
  }
  {
    std::vector<std::string> bed = smallBedJson();
    bed.insert(bed.begin(), boxJson(1e-3, 0.0));
    const v1::Error e = compileError(bed);
    EXPECT_EQ(e.component(), "box");
    EXPECT_EQ(e.field(), "box.simulation_box.time_step");
  }
  {
    const v1::Error e = compileError({boxJson(1e-5, 0.0), glass,
                                      R"({"name": "bucket", "rigid_body": {"material": "glass", "box": {"size": {"x": 0.1, "y": 0.1, "z": 0.1}}}})"});
    EXPECT_EQ(e.field(), "bucket.communication_interval");
  }
}

// An interval of more than 1e8 time steps would stall the server's thread: refused,
// naming the interval, whether the interval is long or the time step tiny (the fuzzer's
// valid 1e-220 s step); 1e8 steps exactly is accepted.
TEST(CosimCompile, IntervalOfTooManyStepsIsRefused) {
  const std::string glass = smallBedJson()[0];
  {
    const v1::Error e = compileError({boxJson(1e-5, 0.0), glass,
                                      R"({"name": "view", "communication_interval": 1000.01, "particle_view": {}})"});
    EXPECT_EQ(e.component(), "view");
    EXPECT_EQ(e.field(), "view.communication_interval");
    EXPECT_NE(e.message().find("1e+08 time steps"), std::string::npos) << e.message();
  }
  {
    const v1::Error e = compileError({R"({"name": "box", "simulation_box": {"time_step": 1e-220}})", glass,
                                      R"({"name": "view", "communication_interval": 0.001, "particle_view": {}})"});
    EXPECT_EQ(e.field(), "view.communication_interval");
    EXPECT_NE(e.message().find("1e-220"), std::string::npos) << e.message();
  }
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  h.declare(1, boxJson(1e-5, 0.0, R"("coupling": {"expected_count": 3})"));
  h.declare(1, glass);
  h.declare(1, R"({"name": "view", "communication_interval": 1000, "particle_view": {}})");
  ASSERT_TRUE(h.compiled(1)) << (h.errors(1).empty() ? "" : h.errors(1)[0].message());
  const v1::Compiled compiled = *h.compiled(1);
  bool found = false;
  for (const v1::CompiledComponent& c : compiled.components()) {
    if (c.name() != "view") continue;
    found = true;
    EXPECT_EQ(c.interval_steps(), 100'000'000u);
  }
  EXPECT_TRUE(found);
}

TEST(CosimCompile, NonMultipleIntervalIsRoundedWithAWarning) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  h.declare(1, boxJson(1e-5, 0.0, R"("coupling": {"expected_count": 3})"));
  h.declare(1, smallBedJson()[0]);
  h.declare(1, R"({"name": "view", "communication_interval": 0.000124, "particle_view": {}})");
  const std::optional<v1::Compiled> c = h.compiled(1);
  ASSERT_TRUE(c);
  ASSERT_EQ(c->components_size(), 3);
  EXPECT_EQ(c->components(2).name(), "view");
  EXPECT_EQ(c->components(2).interval_steps(), 12u);  // 12.4 steps round to 12
  ASSERT_EQ(c->report().warnings_size(), 1);
  EXPECT_NE(c->report().warnings(0).find("view.communication_interval"), std::string::npos);
  EXPECT_NE(c->report().text().find("warning"), std::string::npos);
}

TEST(CosimCompile, ReportSaysWhichThreadCountAutoPicked) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  h.declare(1, boxJson(1e-5, 1e-3, R"("threads": 0, "coupling": {"expected_count": 2})"));
  h.declare(1, smallBedJson()[0]);
  const std::optional<v1::Compiled> c = h.compiled(1);
  ASSERT_TRUE(c);
  const std::string& text = c->report().text();
  EXPECT_NE(text.find("threads: "), std::string::npos) << text;
  EXPECT_NE(text.find("(auto: "), std::string::npos) << text;
  EXPECT_NE(text.find("load average"), std::string::npos) << text;
}

TEST(CosimCompile, ReportHasStagesCriticalStepAndInitialOutputs) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  std::vector<std::string> bed = smallBedJson();
  h.declare(1, boxJson(1e-5, 0.01, R"("coupling": {"expected_count": 5})", 0.001));
  for (const std::string& c : bed) h.declare(1, c);
  h.declare(1, R"({"name": "view", "communication_interval": 0.002, "particle_view": {"max_count": 4}})");
  const std::optional<v1::Compiled> c = h.compiled(1);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->end_step(), 1000u);
  EXPECT_DOUBLE_EQ(c->time_step(), 1e-5);
  EXPECT_GT(c->report().critical_time_step(), 1e-5);
  EXPECT_EQ(c->report().particle_count(), 9u);
  // Exactly what a bed on a plane needs (tests/server/scene/test_scene_stages.cpp covers more scenes).
  const std::vector<std::string> stages(c->report().active_stages().begin(), c->report().active_stages().end());
  EXPECT_EQ(stages, (std::vector<std::string>{"velocity_verlet", "neighbour_list", "forces",
                                              "particle_contacts:hertz_mindlin", "plane_contacts", "second_half_kick",
                                              "advance_clock", "watchdog"}));
  ASSERT_EQ(c->initial_outputs_size(), 2);
  EXPECT_EQ(c->initial_outputs(0).simulation_box().particle_count(), 9u);
  const v1::ParticleViewOutput& view = c->initial_outputs(1).particle_view();
  EXPECT_EQ(view.total_count(), 9u);
  EXPECT_EQ(view.stride(), 3u);  // ceil(9 / 4)
  EXPECT_EQ(view.radii_size(), 3);
  EXPECT_EQ(view.positions_size(), 9);
}

}  // namespace
}  // namespace demlink::server::test
