// The host and its engine: the scene and the server must agree on the backend; on
// LIGGGHTS the host refuses what LIGGGHTS cannot run, naming the component, before any
// engine exists; and a mirror host fed with the leader's events (what the MPI ranks
// other than 0 do, cosim/cosim_lockstep.hpp) holds the very same world, with the
// leader's before_engine called before every stretch of stepping.
#include <gtest/gtest.h>

#include <vector>

#include "cosim_test_support.hpp"
#include "demlink/server/cosim/session_replay.hpp"

namespace demlink::server::test {
namespace {

void declareBed(CosimHarness& h, ConnectionId id, const std::string& boxExtra, std::size_t extraComponents) {
  h.hello(id, "alpha");
  h.declare(id, boxJson(1e-5, 1e-4,
                        boxExtra + R"("coupling": {"expected_count": )" + std::to_string(4 + extraComponents) + "}",
                        2e-5));
  for (const std::string& json : smallBedJson()) h.declare(id, json);
}

TEST(CosimBackend, SceneBackendMustAgreeWithTheServers) {
  ScratchDir dir;
  CosimHarness h(dir.path());  // a native server
  declareBed(h, 1, R"("backend": "LIGGGHTS", )", 0);
  const std::vector<v1::Error> errors = h.errors(1);
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors.back().code(), v1::Error::INVALID_DECLARATION);
  EXPECT_EQ(errors.back().field(), "box.simulation_box.backend");
  EXPECT_EQ(errors.back().component(), "box");
  EXPECT_NE(errors.back().message().find("must agree"), std::string::npos) << errors.back().message();
  EXPECT_TRUE(h.finished(1));
  EXPECT_FALSE(h.host().simulationRunning());
  // Saying NATIVE to a native server is fine.
  declareBed(h, 2, R"("backend": "NATIVE", )", 0);
  EXPECT_TRUE(h.compiled(2)) << (h.errors(2).empty() ? "" : h.errors(2).back().message());
}

TEST(CosimBackend, LiggghtsRefusalNamesTheComponentBeforeAnyEngineExists) {
  ScratchDir dir;
  CosimOptions options = CosimHarness::options(dir.path(), {}, {});
  options.backend = BackendKind::Liggghts;
  int built = 0;
  options.liggghts = [&built](core::World&, const std::filesystem::path&,
                              const std::filesystem::path&) -> std::unique_ptr<SimulationBackend> {
    ++built;
    throw std::runtime_error("no engine in this test");
  };
  CosimHarness h(std::move(options));
  declareBed(h, 1, R"("bounds": {"lower": {"x": -0.01, "y": -0.01, "z": -0.01}, "upper": {"x": 0.03, "y": 0.03,
      "z": 0.03}}, )", 1);
  h.declare(1, R"({"name": "scoop", "clump_template": {"spheres": [
      {"offset": {"x": -0.001}, "radius": 0.001}, {"offset": {"x": 0.001}, "radius": 0.001}]}})");
  const std::vector<v1::Error> errors = h.errors(1);
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors.back().code(), v1::Error::INVALID_DECLARATION);
  EXPECT_EQ(errors.back().component(), "scoop");
  EXPECT_EQ(errors.back().field(), "scoop.clump_template") << "named as the compiler names fields";
  EXPECT_NE(errors.back().message().find("clump_template"), std::string::npos) << errors.back().message();
  EXPECT_NE(errors.back().message().find("LIGGGHTS"), std::string::npos) << errors.back().message();
  EXPECT_EQ(built, 0);
  EXPECT_FALSE(h.host().simulationRunning());
}

TEST(CosimBackend, MirrorReplayingTheLeadersEventsHoldsTheSameWorld) {
  ScratchDir dir;
  std::vector<v1::SessionEvent> events;
  int engineCalls = 0;
  CosimOptions options = CosimHarness::options(dir.path() / "leader", {}, {});
  options.on_event = [&events](const v1::SessionEvent& event) { events.push_back(event); };
  options.before_engine = [&engineCalls] { ++engineCalls; };
  CosimHarness h(std::move(options));
  CosimOptions mirrorOptions = CosimHarness::options(dir.path() / "mirror", {}, {});
  mirrorOptions.mirror = true;
  CosimHost mirror(mirrorOptions);
  std::size_t replayed = 0;
  const auto catchUp = [&] {
    for (; replayed < events.size(); ++replayed) {
      ASSERT_TRUE(replayEvent(mirror, events[replayed], SteadyClock::time_point{}));
    }
  };

  declareBed(h, 1, "", 0);
  ASSERT_TRUE(h.compiled(1));
  const std::uint32_t box = h.idOf(1, "box");
  for (std::uint64_t step = 0; step <= 6; step += 2) h.sample(1, box, step);  // the world is at step 8
  EXPECT_EQ(engineCalls, 4);  // one stretch of stepping per exchange
  catchUp();
  ASSERT_NE(mirror.world(), nullptr);
  ASSERT_NE(h.host().world(), nullptr);
  EXPECT_EQ(mirror.world()->stepCount(), 8u);
  EXPECT_EQ(mirror.world()->particles().position, h.host().world()->particles().position);
  EXPECT_EQ(mirror.world()->particles().velocity, h.host().world()->particles().velocity);
  h.sample(1, box, 8);  // on to the end step, 10
  ASSERT_TRUE(h.finished(1));
  catchUp();
  EXPECT_EQ(mirror.simulationsFinished(), 1u);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "mirror" / "sim_001" / "run_log.csv")) << "a mirror writes no output";
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "leader" / "sim_001" / "run_log.csv"));
}

}  // namespace
}  // namespace demlink::server::test
