/// A headless run and a co-simulation convert the same output and sample intervals by the
/// same rule (core::intervalSteps): a vtk_interval shorter than half a step is refused by
/// both with the same reason, an off-grid one is rounded by both to the same frames.
#include <gtest/gtest.h>

#include "cosim_test_support.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/server/run/headless_runner.hpp"
#include "demlink/server/run/run_driver.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

/// A box with dt = 1e-5 s and end_time 2e-3 s (200 steps), expecting the other three.
std::string box(const std::string& output) {
  return R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.002, )"
         R"("coupling": {"expected_count": 4}, "output": {"progress_interval_s": 60)" +
         output + "}}}";
}

/// "<field> = <value>: <reason>" -> "<value>: <reason>" (the field differs: the headless
/// run names components[i], the co-simulation the component's name).
std::string afterField(const std::string& message, const std::string& field) {
  EXPECT_EQ(message.rfind(field + " = ", 0), 0u) << message;
  return message.substr(std::min(message.size(), field.size() + 3));
}

/// The headless run's InputError message for the scene (empty if it runs).
std::string headlessError(const std::vector<std::string>& components, const std::filesystem::path& out) {
  TranslatedScene scene = translateScene(test::sceneOf(components), {});
  scene.run.output_directory = out.string();
  try {
    (void)runHeadless(scene);
  } catch (const core::InputError& error) {
    return error.what();
  }
  return {};
}

/// The co-simulation's compile error message for the same components declared by a
/// client (empty if it compiles).
std::string cosimError(const std::vector<std::string>& components, const std::filesystem::path& root) {
  test::CosimHarness h(root);
  h.hello(1);
  for (const std::string& c : components) h.declare(1, c);
  const std::vector<v1::Error> errors = h.errors(1);
  return errors.empty() ? std::string() : errors.front().message();
}

TEST(SameIntervalRule, TooShortVtkAndSampleIntervalsAreRefusedAlikeHeadlessAndCoupled) {
  const test::ScratchDir scratch;
  std::vector<std::string> scene = test::smallBedJson();
  scene.insert(scene.begin(), box(R"(, "vtk_interval": 4e-6)"));
  const std::string headless = headlessError(scene, scratch.path() / "h1");
  const std::string coupled = cosimError(scene, scratch.path() / "c1");
  EXPECT_EQ(afterField(headless, "components[0].simulation_box.output.vtk_interval"),
            "4e-06: shorter than half a time step (1e-05 s)");
  EXPECT_EQ(afterField(coupled, "box.simulation_box.output.vtk_interval"),
            afterField(headless, "components[0].simulation_box.output.vtk_interval"));

  scene[0] = box("");
  scene.push_back(
      R"({"name": "fill", "region_sensor": {"region": {"sphere": {"radius": 0.1}}, "sample_interval": 4e-6}})");
  scene[0].replace(scene[0].find("4}"), 2, "5}");  // expected_count: the sensor too
  const std::string headlessSample = headlessError(scene, scratch.path() / "h2");
  const std::string coupledSample = cosimError(scene, scratch.path() / "c2");
  EXPECT_EQ(afterField(coupledSample, "fill.region_sensor.sample_interval"),
            afterField(headlessSample, "components[4].region_sensor.sample_interval"));
}

TEST(SameIntervalRule, OffGridVtkIntervalIsRoundedToTheSameFramesHeadlessAndCoupled) {
  const test::ScratchDir scratch;
  std::vector<std::string> scene = test::smallBedJson();
  scene.insert(scene.begin(), box(R"(, "vtk_interval": 0.000124, "checkpoint_interval": 0.001054)"));

  TranslatedScene headless = translateScene(test::sceneOf(scene), {});
  const RunPlan plan = planRun(headless.run, 1e-5, true);
  ASSERT_EQ(plan.warnings.size(), 2u);
  headless.run.output_directory = (scratch.path() / "headless").string();
  const RunSummary summary = runHeadless(headless);
  EXPECT_EQ(summary.frames, 18u) << "steps 0, 12, ..., 192 and the end, 200";
  EXPECT_EQ(summary.checkpoints, 2u) << "step 105 and the final one";

  test::CosimHarness h(scratch.path() / "cosim");
  h.hello(1);
  for (const std::string& c : scene) h.declare(1, c);
  const std::optional<v1::Compiled> compiled = h.compiled(1);
  ASSERT_TRUE(compiled) << (h.errors(1).empty() ? "" : h.errors(1)[0].message());
  ASSERT_TRUE(h.finished(1));
  const v1::CompileReport& report = compiled->report();
  ASSERT_EQ(report.warnings_size(), 2);
  for (int k = 0; k < 2; ++k) {
    const std::string field =
        k == 0 ? ".simulation_box.output.vtk_interval" : ".simulation_box.output.checkpoint_interval";
    EXPECT_EQ(afterField(report.warnings(k), "box" + field), afterField(plan.warnings[k], "components[0]" + field));
  }
  const std::filesystem::path sim = h.finished(1)->output_directory();
  const std::filesystem::path alone = scratch.path() / "headless";
  EXPECT_EQ(test::readText(sim / "particles.pvd"), test::readText(alone / "particles.pvd")) << "same frame times";
  for (const char* file : {"particles_000017.vtp", "checkpoint_000001.bin", "checkpoint_final.bin"}) {
    EXPECT_TRUE(std::filesystem::exists(sim / file)) << file;
    EXPECT_TRUE(std::filesystem::exists(alone / file)) << file;
  }
  EXPECT_FALSE(std::filesystem::exists(sim / "particles_000018.vtp"));
  EXPECT_EQ(test::readText(sim / "checkpoint_final.bin"), test::readText(alone / "checkpoint_final.bin"))
      << "same world, same steps";
}

}  // namespace
}  // namespace demlink::server
