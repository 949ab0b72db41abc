// Recorder and replay: a recorded session replays to a bit-identical final checkpoint.
// Equivalence: a rigid body pushing into a small bed, driven by a client through the host,
// ends bit-identical to the same scene driven in-process by core::CoupledMotion (the
// reference the loopback TCP test compares against).
#include <gtest/gtest.h>

#include <sstream>

#include "cosim_test_support.hpp"
#include "demlink/core/walls/coupled_motion.hpp"
#include "demlink/server/cosim/session_replay.hpp"

namespace demlink::server::test {
namespace {

constexpr std::uint64_t kInterval = 20;  // steps of 1e-5 s
constexpr std::uint64_t kSamples = 40;

std::vector<std::string> pusherScene() {
  std::vector<std::string> c = smallBedJson(4);
  c.insert(c.begin(), boxJson(1e-5, 0.0));
  c.push_back(R"({"name": "blade", "communication_interval": 0.0002, "rigid_body": {"material": "glass",
      "box": {"size": {"x": 0.004, "y": 0.03, "z": 0.01}}, "position": {"x": -0.006, "y": 0.006, "z": 0.005},
      "motion": "PREDICTED"}})");
  return c;
}

/// The blade's prescribed trajectory: pushes along +x at 0.5 m/s while turning slowly.
std::pair<core::RigidPose, core::RigidTwist> blade(std::uint64_t sample) {
  const double t = static_cast<double>(sample * kInterval) * 1e-5;
  const core::Vec3 omega(0.0, 0.0, 0.5);
  core::RigidPose pose;
  pose.position = core::Vec3(-0.006 + 0.5 * t, 0.006, 0.005);
  pose.orientation = core::Quat(Eigen::AngleAxisd(0.5 * t, core::Vec3::UnitZ()));
  return {pose, core::RigidTwist{core::Vec3(0.5, 0.0, 0.0), omega}};
}

/// Runs the pusher session through a host (one client declaring everything; quiet-period
/// compile via poll); returns the output directory.
std::filesystem::path runPusher(const std::filesystem::path& root, const std::filesystem::path& record = {}) {
  CosimHarness h(root, {}, record);
  h.hello(1, "pusher");
  for (const std::string& c : pusherScene()) h.declare(1, c);
  h.advanceClock(2.5);
  h.poll();
  EXPECT_TRUE(h.compiled(1));
  const std::uint32_t id = h.idOf(1, "blade");
  for (std::uint64_t k = 0; k < kSamples; ++k) {
    const auto [pose, twist] = blade(k);
    h.sampleBody(1, id, k * kInterval, bodyInput(pose.position, pose.orientation, twist.linear, twist.angular));
  }
  h.bye(1);
  EXPECT_TRUE(h.errors(1).empty());
  EXPECT_TRUE(h.finished(1));
  return h.finished(1) ? std::filesystem::path(h.finished(1)->output_directory()) : std::filesystem::path();
}

TEST(CosimReplay, ReplayedSessionEndsBitIdentical) {
  ScratchDir dir;
  const std::filesystem::path live = runPusher(dir.path() / "live", dir.path() / "session.rec");
  ASSERT_TRUE(std::filesystem::exists(live / "checkpoint_final.bin"));
  CosimOptions options;
  options.output_root = dir.path() / "replay";
  const ReplayResult replay = replaySession(dir.path() / "session.rec", options);
  EXPECT_EQ(replay.simulations, 1u);
  ASSERT_EQ(replay.finished.size(), 1u);
  EXPECT_EQ(replay.finished[0].reason(), "said Bye");
  EXPECT_EQ(replay.finished[0].step(), kSamples * kInterval);
  EXPECT_TRUE(replay.errors.empty());
  const std::string liveBytes = fileBytes(live / "checkpoint_final.bin");
  const std::string replayBytes = fileBytes(replay.output_directory / "checkpoint_final.bin");
  EXPECT_GT(liveBytes.size(), 1000u);
  EXPECT_TRUE(liveBytes == replayBytes);
}

TEST(CosimReplay, TruncatedRecordIsRefused) {
  ScratchDir dir;
  runPusher(dir.path() / "live", dir.path() / "session.rec");
  std::string bytes = fileBytes(dir.path() / "session.rec");
  bytes.resize(bytes.size() - 3);
  writeText(dir.path() / "cut.rec", bytes);
  CosimOptions options;
  options.output_root = dir.path() / "replay";
  EXPECT_THROW((void)replaySession(dir.path() / "cut.rec", options), std::runtime_error);
}

TEST(CosimEquivalence, ClientDrivenBodyMatchesInProcessPrescribedMotion) {
  ScratchDir dir;
  const std::filesystem::path live = runPusher(dir.path());
  // The same declarations, translated and driven directly by the engine-level coupling.
  TranslatedScene scene = translateScene(sceneOf(pusherScene()), {}, SceneUse::Cosim);
  core::World& world = scene.world;
  world.initialize();
  ASSERT_EQ(world.meshes().size(), 1u);
  core::CoupledMotion motion(0, core::MotionMode::Predicted);
  for (std::uint64_t k = 0; k < kSamples; ++k) {
    const auto [pose, twist] = blade(k);
    motion.beginInterval(world.mesh(motion.meshIndex()), world.settings().time_step, pose, twist, kInterval);
    for (std::uint64_t s = 0; s < kInterval; ++s) {
      world.step();
      motion.afterStep(world.meshes()[motion.meshIndex()], world.settings().time_step);
    }
    (void)motion.endInterval(world.mesh(motion.meshIndex()), world.settings().time_step);
  }
  motion.hold(world.mesh(motion.meshIndex()));  // the client said Bye: the body stops where it is
  // The blade really pushed particles.
  double fastest = 0.0;
  for (const core::Vec3& v : world.particles().velocity) fastest = std::max(fastest, v.x());
  EXPECT_GT(fastest, 0.1);
  std::ostringstream bytes;
  world.saveCheckpoint(bytes);
  const std::string reference = bytes.str();
  EXPECT_TRUE(reference == fileBytes(live / "checkpoint_final.bin"));
}

}  // namespace
}  // namespace demlink::server::test
