// Restoring a co-simulation from one of its checkpoints (CosimOptions::restore_file,
// demlink-server --restore) on our engine: a client's blade pushes into a bed; the
// simulation restored from the checkpoint written half way, given the same packages from
// there on, answers the same wrenches and ends with the same final checkpoint, byte for
// byte, as the run that never stopped. A checkpoint in the middle of an exchange interval,
// or at the end, is refused naming the restore.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cosim_test_support.hpp"

namespace demlink::server::test {
namespace {

constexpr std::uint64_t kInterval = 20;   // steps of 1e-5 s per exchange
constexpr std::uint64_t kSamples = 40;    // the end: step 800
constexpr std::uint64_t kRestoredAt = 400;  // checkpoint_000001 (checkpoint_interval 4 ms)

/// A blade that pushes into a bed along +x at 0.5 m/s while turning about z, exchanged
/// every kInterval steps; `checkpointInterval` [s] in the box's output.
std::vector<std::string> pusherScene(const std::string& checkpointInterval) {
  std::vector<std::string> c = smallBedJson(4);
  c.insert(c.begin(), R"({"name": "box", "simulation_box": {"time_step": 1e-5, "end_time": 0.008,
      "restitution_tolerance": 0.2, "output": {"checkpoint_interval": )" + checkpointInterval + "}}}");
  c.push_back(R"({"name": "blade", "communication_interval": 0.0002, "rigid_body": {"material": "glass",
      "box": {"size": {"x": 0.004, "y": 0.03, "z": 0.01}}, "position": {"x": -0.006, "y": 0.006, "z": 0.005},
      "motion": "PREDICTED"}})");
  return c;
}

v1::RigidBodyInput bladeAt(std::uint64_t step) {
  const double t = static_cast<double>(step) * 1e-5;
  return bodyInput(core::Vec3(-0.006 + 0.5 * t, 0.006, 0.005), core::Quat(Eigen::AngleAxisd(0.5 * t, core::Vec3::UnitZ())),
                   core::Vec3(0.5, 0.0, 0.0), core::Vec3(0.0, 0.0, 0.5));
}

struct PusherRun {
  std::optional<v1::Compiled> compiled;
  std::vector<v1::DataPackage> answers;  ///< the blade's, in order
  std::vector<v1::Error> errors;
  std::filesystem::path output;  ///< the simulation's folder; empty if it did not finish
};

/// The pusher session through a host whose options restore `restore` (empty: from step 0):
/// the client sends the blade's package at every due step from the start step to the end.
PusherRun runPusher(const std::filesystem::path& root, const std::string& checkpointInterval,
                    const std::filesystem::path& restore = {}) {
  CosimOptions options = CosimHarness::options(root, {}, {});
  options.restore_file = restore;
  CosimHarness h(options);
  h.hello(1, "pusher");
  for (const std::string& c : pusherScene(checkpointInterval)) h.declare(1, c);
  h.advanceClock(2.5);
  h.poll();
  PusherRun run;
  run.compiled = h.compiled(1);
  if (run.compiled) {
    const std::uint32_t id = h.idOf(1, "blade");
    for (std::uint64_t step = run.compiled->start_step(); step < kSamples * kInterval; step += kInterval) {
      h.sampleBody(1, id, step, bladeAt(step));
    }
  }
  run.answers = h.data(1);
  run.errors = h.errors(1);
  if (const std::optional<v1::Finished> finished = h.finished(1); finished && run.errors.empty()) {
    run.output = finished->output_directory();
  }
  return run;
}

TEST(CosimRestore, RestoredHalfWayContinuesAsTheUnbrokenRun) {
  ScratchDir dir;
  const PusherRun unbroken = runPusher(dir.path() / "unbroken", "0.004");
  ASSERT_TRUE(unbroken.errors.empty()) << unbroken.errors[0].message();
  ASSERT_FALSE(unbroken.output.empty());
  ASSERT_EQ(unbroken.answers.size(), kSamples);
  const std::filesystem::path checkpoint = unbroken.output / "checkpoint_000001.bin";
  ASSERT_TRUE(std::filesystem::exists(checkpoint));

  const PusherRun restored = runPusher(dir.path() / "restored", "0.004", checkpoint);
  ASSERT_TRUE(restored.errors.empty()) << restored.errors[0].message();
  ASSERT_TRUE(restored.compiled);
  EXPECT_EQ(restored.compiled->start_step(), kRestoredAt);
  ASSERT_EQ(restored.compiled->initial_outputs_size(), 1);
  EXPECT_EQ(restored.compiled->initial_outputs(0).step(), kRestoredAt) << "the outputs at the start step";
  ASSERT_EQ(restored.answers.size(), kSamples - kRestoredAt / kInterval);
  // Every answer after the restore, wrench and pose, equals the unbroken run's.
  double largest = 0.0;
  for (std::size_t k = 0; k < restored.answers.size(); ++k) {
    const v1::DataPackage& a = unbroken.answers[kRestoredAt / kInterval + k];
    const v1::DataPackage& b = restored.answers[k];
    ASSERT_EQ(a.step(), b.step());
    EXPECT_EQ(a.rigid_body().SerializeAsString(), b.rigid_body().SerializeAsString())
        << "step " << b.step();
    largest = std::max(largest, std::abs(b.rigid_body().mean_force().x()));
  }
  EXPECT_GT(largest, 1e-3) << "the blade pushes the bed after the restore";
  const std::string unbrokenEnd = fileBytes(unbroken.output / "checkpoint_final.bin");
  EXPECT_GT(unbrokenEnd.size(), 1000u);
  EXPECT_TRUE(unbrokenEnd == fileBytes(restored.output / "checkpoint_final.bin"));
}

TEST(CosimRestore, CheckpointInsideAnIntervalIsRefusedNamingTheComponent) {
  ScratchDir dir;
  // Every 10 steps: checkpoint_000001 is at step 10, half way through the blade's interval.
  const PusherRun unbroken = runPusher(dir.path() / "unbroken", "0.0001");
  ASSERT_FALSE(unbroken.output.empty());
  const PusherRun restored = runPusher(dir.path() / "restored", "0.0001", unbroken.output / "checkpoint_000001.bin");
  ASSERT_FALSE(restored.errors.empty());
  const std::string what = restored.errors[0].message();
  EXPECT_NE(what.find("restore"), std::string::npos) << what;
  EXPECT_NE(what.find("step 10"), std::string::npos) << what;
  EXPECT_NE(what.find("\"blade\""), std::string::npos) << what;
  EXPECT_FALSE(restored.compiled);

  const PusherRun ended = runPusher(dir.path() / "ended", "0.0001", unbroken.output / "checkpoint_final.bin");
  ASSERT_FALSE(ended.errors.empty());
  EXPECT_NE(ended.errors[0].message().find("nothing left to run"), std::string::npos) << ended.errors[0].message();
}

}  // namespace
}  // namespace demlink::server::test
