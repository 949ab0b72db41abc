// Co-simulation exchange: the scheduler rule (multi-rate components exchange exactly at
// their own sample steps), scene-file components mixed with remote ones, a sensor riding
// on a client's rigid body, the mass balance of a source and a sink, and the live view's
// hook (CosimOptions::step_observer) seeing every step with the same balance.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

#include "cosim_test_support.hpp"
#include "demlink/core/components/region_sensor.hpp"
#include "demlink/server/cosim/cosim_simulation.hpp"
#include "demlink/server/cosim/exchange_scheduler.hpp"
#include "demlink/server/view/live_view_hub.hpp"

namespace demlink::server::test {
namespace {

TEST(ExchangeScheduler, StartsAtARestoredStepWhereEveryComponentIsDue) {
  ExchangeScheduler s;
  s.add(0, 2);
  s.add(1, 5);
  EXPECT_THROW(s.startAt(15), std::invalid_argument) << "component 0 is half way through its interval";
  s.startAt(20);
  EXPECT_EQ(s.currentStep(), 20u);
  EXPECT_EQ(s.missing(), (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(s.offer(0, 0), ExchangeScheduler::Offer::WrongStep);
  EXPECT_EQ(s.offer(0, 20), ExchangeScheduler::Offer::Accepted);
  EXPECT_EQ(s.offer(1, 20), ExchangeScheduler::Offer::Accepted);
  EXPECT_EQ(s.nextStop(0), 22u);
  s.advanceTo(22);
  EXPECT_THROW(s.startAt(30), std::invalid_argument) << "the grid has started";
}

TEST(ExchangeScheduler, DueStepsAndStops) {
  ExchangeScheduler s;
  s.add(0, 2);
  s.add(1, 5);
  EXPECT_EQ(s.missing(), (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(s.offer(0, 1), ExchangeScheduler::Offer::WrongStep);
  EXPECT_EQ(s.offer(0, 0), ExchangeScheduler::Offer::Accepted);
  EXPECT_EQ(s.offer(0, 0), ExchangeScheduler::Offer::AlreadyReceived);
  EXPECT_EQ(s.offer(0, 2), ExchangeScheduler::Offer::NotDue);
  EXPECT_FALSE(s.complete());
  EXPECT_EQ(s.offer(1, 0), ExchangeScheduler::Offer::Accepted);
  EXPECT_TRUE(s.complete());
  EXPECT_EQ(s.nextStop(0), 2u);
  EXPECT_EQ(s.nextStop(1), 1u);  // capped at the end step
  EXPECT_EQ(s.advanceTo(2), (std::vector<std::size_t>{0}));
  EXPECT_EQ(s.expectedStep(1), 5u);
  EXPECT_EQ(s.offer(0, 2), ExchangeScheduler::Offer::Accepted);
  EXPECT_EQ(s.nextStop(0), 4u);
  s.advanceTo(4);
  s.offer(0, 4);
  EXPECT_EQ(s.nextStop(0), 5u);
  EXPECT_EQ(s.advanceTo(5), (std::vector<std::size_t>{1}));
  s.retire(1);
  EXPECT_EQ(s.offer(1, 5), ExchangeScheduler::Offer::NotExchanged);
  EXPECT_TRUE(s.complete());
  s.retire(0);
  EXPECT_FALSE(s.nextStop(0));
  EXPECT_EQ(s.nextStop(9), 9u);
}

TEST(CosimExchange, MultiRateComponentsExchangeAtTheirOwnSampleSteps) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  // dt = 0.5 ms; intervals 1, 2 and 5 ms = 2, 4 and 10 steps; end at 20 ms = step 40.
  h.declare(1, boxJson(5e-4, 0.02, R"("coupling": {"expected_count": 4, "strict_intervals": true})", 0.001));
  h.declare(1, smallBedJson()[0]);
  h.declare(1, R"({"name": "zone", "communication_interval": 0.002, "region_sensor": {"region": {"sphere": {"radius": 0.1}}}})");
  h.declare(1, R"({"name": "view", "communication_interval": 0.005, "particle_view": {}})");
  ASSERT_TRUE(h.compiled(1));
  const std::map<std::uint32_t, std::uint64_t> interval{
      {h.idOf(1, "box"), 2}, {h.idOf(1, "zone"), 4}, {h.idOf(1, "view"), 10}};
  std::map<std::uint32_t, std::vector<std::uint64_t>> answered;
  std::size_t read = h.inbox(1).size();
  for (const auto& [id, n] : interval) h.sample(1, id, 0);
  while (read < h.inbox(1).size()) {
    const v1::ServerMessage m = h.inbox(1)[read++];
    if (!m.has_data()) continue;
    const std::uint32_t id = m.data().component_id();
    ASSERT_TRUE(interval.contains(id));
    answered[id].push_back(m.data().step());
    // The world is exactly at the answered step when the answer goes out.
    if (h.host().world() != nullptr) {
      EXPECT_EQ(h.host().world()->stepCount(), m.data().step());
    }
    if (h.finished(1)) continue;
    h.sample(1, id, m.data().step());
  }
  ASSERT_TRUE(h.finished(1));
  EXPECT_EQ(h.finished(1)->step(), 40u);
  EXPECT_EQ(h.finished(1)->reason(), "end time reached");
  EXPECT_TRUE(h.errors(1).empty());
  for (const auto& [id, n] : interval) {
    std::vector<std::uint64_t> expected;
    for (std::uint64_t s = n; s <= 40; s += n) expected.push_back(s);
    EXPECT_EQ(answered[id], expected) << "component " << id;
  }
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "sim_001" / "checkpoint_final.bin"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "sim_001" / "region_sensor_zone.csv"));
}

TEST(CosimExchange, SceneFileAndRemoteComponentsMixAndSensorsFollowTheBody) {
  ScratchDir dir;
  std::vector<std::string> base = smallBedJson();
  base.push_back(boxJson(1e-5, 0.0, R"("coupling": {"expected_names": ["plate", "fill"]})"));
  CosimHarness h(dir.path(), sceneOf(base));
  h.hello(1, "excavator");
  h.declare(1, R"({"name": "plate", "communication_interval": 0.0002, "rigid_body": {"material": "glass",
      "box": {"size": {"x": 0.02, "y": 0.02, "z": 0.002}}, "position": {"z": 0.05}, "motion": "LAGGED"}})");
  h.declare(1, R"({"name": "fill", "communication_interval": 0.0002, "region_sensor": {"region": {
      "box": {"centre": {"z": 0.005}, "size": {"x": 0.02, "y": 0.02, "z": 0.01}}, "attached_to": "plate"}}})");
  const std::optional<v1::Compiled> c = h.compiled(1);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->all_components_size(), 6);
  EXPECT_EQ(c->components_size(), 2);
  for (const v1::CompiledComponent& k : c->all_components()) {
    EXPECT_EQ(k.remote(), k.name() == "plate" || k.name() == "fill") << k.name();
  }
  const std::uint32_t plate = h.idOf(1, "plate");
  const std::uint32_t fill = h.idOf(1, "fill");
  const core::Quat turn(Eigen::AngleAxisd(0.3, core::Vec3::UnitZ()));
  for (std::uint64_t k = 0; k < 5; ++k) {
    const std::uint64_t step = 20 * k;
    h.sampleBody(1, plate, step, bodyInput({0.001 * static_cast<double>(k), 0.0, 0.05}, turn));
    h.sample(1, fill, step);
  }
  ASSERT_TRUE(h.errors(1).empty()) << h.errors(1)[0].message();
  const CosimSimulation* sim = h.host().simulation();
  ASSERT_NE(sim, nullptr);
  const core::World& world = *h.host().world();
  const core::MeshBody& mesh = world.meshes().at(0);
  EXPECT_EQ(mesh.name(), "plate");
  // LAGGED: at step 100 the plate is on the pose sent at step 80.
  EXPECT_NEAR(mesh.position().x(), 0.004, 1e-15);
  const auto* sensor = dynamic_cast<const core::RegionSensor*>(sim->components()[fill - 1].engine);
  ASSERT_NE(sensor, nullptr);
  const core::RegionPose pose = sensor->placement().poseAt(world.meshes(), world.time());
  EXPECT_NEAR((pose.centre - (mesh.position() + mesh.orientation() * core::Vec3(0, 0, 0.005))).norm(), 0.0, 1e-15);
  const std::optional<v1::DataPackage> last = h.lastData(1, fill);
  ASSERT_TRUE(last);
  EXPECT_EQ(last->step(), 100u);
  EXPECT_EQ(last->region_sensor().count(), 0u);  // the bed is 5 cm below
  h.bye(1);
  ASSERT_TRUE(h.finished(1));
  EXPECT_EQ(h.finished(1)->reason(), "said Bye");
  EXPECT_FALSE(h.host().simulationRunning());
}

TEST(CosimExchange, SourceAndSinkCountsBalanceTheWorldsMass) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1);
  h.declare(1, boxJson(2e-5, 0.06, R"("coupling": {"expected_count": 6})", 0.002));
  for (const std::string& c : smallBedJson(2)) h.declare(1, c);
  h.declare(1, R"({"name": "pour", "communication_interval": 0.002, "particle_source": {"material": "glass",
      "sizes": {"uniform": {"r_min": 0.0015, "r_max": 0.002}}, "box": {"lower": {"x": 0.03, "y": -0.01, "z": 0.01},
      "upper": {"x": 0.05, "y": 0.01, "z": 0.02}}, "rate_particles_per_s": 3000, "velocity": {"z": -0.5}, "seed": 7}})");
  h.declare(1, R"({"name": "drain", "communication_interval": 0.004, "particle_sink": {"region": {"box":
      {"centre": {"x": 0.04, "z": 0.003}, "size": {"x": 0.03, "y": 0.03, "z": 0.006}}}}})");
  ASSERT_TRUE(h.compiled(1));
  const double initialMass = h.compiled(1)->initial_outputs(0).simulation_box().total_mass();
  std::size_t read = h.inbox(1).size();
  for (const char* name : {"box", "pour", "drain"}) h.sample(1, h.idOf(1, name), 0);
  std::uint64_t sinkIntervalSum = 0;
  std::uint64_t sourceIntervalSum = 0;
  while (read < h.inbox(1).size()) {
    const v1::ServerMessage m = h.inbox(1)[read++];
    if (!m.has_data()) continue;
    if (m.data().has_particle_sink()) sinkIntervalSum += m.data().particle_sink().interval().count();
    if (m.data().has_particle_source()) sourceIntervalSum += m.data().particle_source().interval().count();
    if (!h.finished(1)) h.sample(1, m.data().component_id(), m.data().step());
  }
  ASSERT_TRUE(h.finished(1));
  const v1::SourceSinkOutput source = h.lastData(1, h.idOf(1, "pour"))->particle_source();
  const v1::SourceSinkOutput sink = h.lastData(1, h.idOf(1, "drain"))->particle_sink();
  const v1::SimulationBoxOutput box = h.lastData(1, h.idOf(1, "box"))->simulation_box();
  EXPECT_GT(source.total().count(), 50u);
  EXPECT_GT(sink.total().count(), 0u);
  EXPECT_EQ(sourceIntervalSum, source.total().count());
  EXPECT_EQ(sinkIntervalSum, sink.total().count());
  EXPECT_EQ(box.particle_count(), 4 + source.total().count() - sink.total().count());
  const double balance = initialMass + source.total().mass() - sink.total().mass();
  EXPECT_NEAR(box.total_mass(), balance, 1e-9 * balance);
}

TEST(CosimExchange, StepObserverSeesEveryStepAndTheViewsMassBalanceHolds) {
  ScratchDir dir;
  LiveViewHub hub;
  hub.setDemand(1.0e9, {true, false});  // a capture at every offer
  std::uint64_t calls = 0;
  std::uint64_t lastStep = 0;
  CosimOptions options = CosimHarness::options(dir.path(), {}, {});
  std::string openedAs;
  std::uint64_t callsWhenOpened = 99;
  options.open_observer = [&](const core::World& world, const std::string& name) {
    openedAs = name;
    callsWhenOpened = calls;
    hub.announce(world, name);
  };
  options.step_observer = [&](const core::World& world) {
    ++calls;
    lastStep = world.stepCount();
    hub.offer(world);
  };
  CosimHarness h(options);
  h.hello(1);
  h.declare(1, boxJson(2e-5, 0.04, R"("coupling": {"expected_count": 6})", 0.002));
  for (const std::string& c : smallBedJson(2)) h.declare(1, c);
  h.declare(1, R"({"name": "pour", "communication_interval": 0.002, "particle_source": {"material": "glass",
      "sizes": {"uniform": {"r_min": 0.0015, "r_max": 0.002}}, "box": {"lower": {"x": 0.03, "y": -0.01, "z": 0.01},
      "upper": {"x": 0.05, "y": 0.01, "z": 0.02}}, "rate_particles_per_s": 3000, "velocity": {"z": -0.5}, "seed": 7}})");
  h.declare(1, R"({"name": "drain", "communication_interval": 0.004, "particle_sink": {"region": {"box":
      {"centre": {"x": 0.04, "z": 0.003}, "size": {"x": 0.03, "y": 0.03, "z": 0.006}}}}})");
  ASSERT_TRUE(h.compiled(1));
  std::size_t read = h.inbox(1).size();
  for (const char* name : {"box", "pour", "drain"}) h.sample(1, h.idOf(1, name), 0);
  while (read < h.inbox(1).size()) {
    const v1::ServerMessage m = h.inbox(1)[read++];
    if (m.has_data() && !h.finished(1)) h.sample(1, m.data().component_id(), m.data().step());
  }
  ASSERT_TRUE(h.finished(1));
  // Once at the start, then after every step.
  EXPECT_EQ(lastStep, 2000u);
  EXPECT_EQ(calls, lastStep + 1);
  // Named once, by its output folder, before its first step was observed.
  EXPECT_EQ(openedAs, "sim_001");
  EXPECT_EQ(callsWhenOpened, 0u);
  EXPECT_NE(hub.simulationsJson().find(R"("name":"sim_001")"), std::string::npos) << hub.simulationsJson();
  std::uint64_t version = 0;
  const ViewSnapshot* snapshot = hub.snapshot(0, version);
  ASSERT_NE(snapshot, nullptr);
  EXPECT_EQ(version, calls);
  const ViewStatus& status = snapshot->status;
  EXPECT_EQ(status.step, lastStep);
  const v1::SimulationBoxOutput box = h.lastData(1, h.idOf(1, "box"))->simulation_box();
  EXPECT_EQ(snapshot->particleCount(), box.particle_count());
  EXPECT_NEAR(status.particle_mass, box.total_mass(), 1e-12 * box.total_mass());
  EXPECT_GT(status.inserted_mass, 0.0);
  EXPECT_GT(status.removed_mass, 0.0);
  EXPECT_NEAR(status.initial_mass + status.inserted_mass - status.removed_mass, status.particle_mass,
              1e-9 * status.particle_mass);
  EXPECT_EQ(snapshot->regions.size(), 1u);  // the sink's box
}

}  // namespace
}  // namespace demlink::server::test
