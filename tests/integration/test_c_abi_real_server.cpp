/// The C ABI against the real demlink-server (a child process: the C ABI's shared library
/// carries its own protobuf messages and cannot share a process with the server's). One
/// client declares a whole scene with the typed calls, says dl_declarations_done (the
/// server's quiet period is far away and no count is given), exchanges every exchanged kind
/// and changes a source, a sink and a sensor at run time. Every value checked has a closed
/// form: free fall, particle masses, the STL's bounds, crossings along the normal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "demlink/demlink_c.h"

namespace demlink::integration {
namespace {

constexpr double kDt = 1.0e-5;            // [s]
constexpr int kSteps = 100;               // steps per communication interval
constexpr double kInterval = kSteps * kDt;  // [s]
constexpr double kDensity = 2500.0;       // [kg/m^3]
constexpr double kG = 9.81;               // [m/s^2]

double sphereMass(double radius) { return kDensity * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius; }

/// One client with every component, stepped in the explicit receive-first order (one call
/// per component and sample; the send-first orders are tested against the fake server).
struct ClientGuard {
  ClientGuard() { (void)dl_set_exchange_order(client, DL_ORDER_RECEIVE_FIRST); }
  dl_client* client = dl_client_create();
  ~ClientGuard() { dl_client_destroy(client); }
};

class CAbiRealServer : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = std::filesystem::temp_directory_path() / ("demlink_c_abi_real_" + std::to_string(::getpid()));
    std::filesystem::remove_all(root_);
    std::filesystem::create_directories(root_ / "data");
    std::filesystem::copy_file(std::filesystem::path(DEMLINK_SOURCE_DIR) / "examples/scenes/meshes/paddle.stl",
                               root_ / "data" / "paddle.stl");
    server_ = std::make_unique<ServerChild>(
        DEMLINK_SERVER_EXE, std::vector<std::string>{"--once", "--output", (root_ / "out").string(), "--data-root",
                                                     (root_ / "data").string(), "--quiet-period", "1000"});
  }
  void TearDown() override {
    if (!HasFailure()) std::filesystem::remove_all(root_);
  }
  std::filesystem::path root_;
  std::unique_ptr<ServerChild> server_;
};

TEST_F(CAbiRealServer, EveryTypedCallAgainstTheServerWithDeclarationsDoneAndRunTimeInputs) {
  ASSERT_GT(server_->port, 0) << server_->announced;
  ClientGuard g;
  dl_client* c = g.client;
  ASSERT_EQ(dl_set_timeout(c, 30.0), DL_OK);
  ASSERT_EQ(dl_connect_to_host(c, server_->host.c_str(), server_->port, "c_abi", nullptr), DL_OK) << dl_last_error(c);
  // A tool repeating its initialisation: the same connect is a no-op, another is refused.
  EXPECT_EQ(dl_connect_to_host(c, server_->host.c_str(), server_->port, "c_abi", nullptr), DL_OK) << dl_last_error(c);
  EXPECT_EQ(dl_connect_to_host(c, server_->host.c_str(), server_->port, "other", nullptr), DL_ERR_STATE);

  const double nan = std::nan("");
  const double gravity[3] = {0.0, 0.0, -kG};
  const double lower[3] = {-0.3, -0.3, -0.05};
  const double upper[3] = {0.3, 0.3, 0.6};
  int box = -1, glass = -1, floor = -1, ball = -1, bed = -1, feed = -1, drain = -1, gate = -1, probe = -1;
  int view = -1, paddle = -1;
  // No end time (NaN) and no count: the run ends with dl_finish, the compile with dl_declarations_done.
  ASSERT_EQ(dl_declare_simulation_box(c, "box", kInterval, kDt, nan, gravity, lower, upper, 0, &box), DL_OK)
      << dl_last_error(c);
  ASSERT_EQ(dl_declare_material(c, "glass", "", kDensity, 5e6, 0.3, 0.5, 0.5, 0.0, &glass), DL_OK) << dl_last_error(c);
  const double origin[3] = {0.0, 0.0, 0.0};
  const double up[3] = {0.0, 0.0, 1.0};
  ASSERT_EQ(dl_declare_plane(c, "floor", origin, up, "glass", &floor), DL_OK) << dl_last_error(c);
  const double ballStart[3] = {0.2, 0.2, 0.4};
  const double still[3] = {0.0, 0.0, 0.0};
  ASSERT_EQ(dl_declare_single_particle(c, "ball", "glass", ballStart, still, 0.01, &ball), DL_OK) << dl_last_error(c);
  const double bedLower[3] = {-0.05, -0.05, 0.0};
  const double bedUpper[3] = {0.05, 0.05, 0.05};
  ASSERT_EQ(dl_declare_pit_generator(c, "bed", "glass", bedLower, bedUpper, 0.004, 0.004, 0.012, 7, &bed), DL_OK)
      << dl_last_error(c);
  const double feedCentre[3] = {0.0, 0.0, 0.17};
  const double feedHalf[3] = {0.03, 0.03, 0.005};
  const double down[3] = {0.0, 0.0, -2.0};
  ASSERT_EQ(dl_declare_particle_source_box(c, "feed", kInterval, "glass", feedCentre, feedHalf, 0.002, 0.002, 4000.0,
                                           -1.0, down, 3, &feed),
            DL_OK)
      << dl_last_error(c);
  const double drainCentre[3] = {-0.2, -0.2, 0.4};
  const double drainSize[3] = {0.03, 0.03, 0.03};
  ASSERT_EQ(dl_declare_particle_sink_box(c, "drain", kInterval, drainCentre, drainSize, &drain), DL_OK)
      << dl_last_error(c);
  const double gateCentre[3] = {0.0, 0.0, 0.15};
  ASSERT_EQ(dl_declare_flow_sensor_disc(c, "gate", kInterval, gateCentre, up, 0.06, "", &gate), DL_OK)
      << dl_last_error(c);
  ASSERT_EQ(dl_declare_region_sensor_sphere(c, "probe", kInterval, ballStart, 0.03, "", &probe), DL_OK)
      << dl_last_error(c);
  ASSERT_EQ(dl_declare_particle_view(c, "view", kInterval, 50, &view), DL_OK) << dl_last_error(c);
  const double paddlePose[7] = {0.2, -0.2, 0.4, 1.0, 0.0, 0.0, 0.0};
  ASSERT_EQ(dl_declare_rigid_body_stl(c, "paddle", kInterval, "paddle.stl", "glass", origin, paddlePose, 2, &paddle),
            DL_OK)
      << dl_last_error(c);

  // Declared again with the same values: the same handle, nothing sent; other values: refused.
  int again = -1;
  EXPECT_EQ(dl_declare_material(c, "glass", "", kDensity, 5e6, 0.3, 0.5, 0.5, 0.0, &again), DL_OK) << dl_last_error(c);
  EXPECT_EQ(again, glass);
  EXPECT_EQ(dl_declare_material(c, "glass", "", 1000.0, 5e6, 0.3, 0.5, 0.5, 0.0, &again), DL_ERR_STATE);

  ASSERT_EQ(dl_declarations_done(c), DL_OK) << dl_last_error(c);
  ASSERT_EQ(dl_declarations_done(c), DL_OK) << "idempotent";
  ASSERT_EQ(dl_wait_compiled(c), DL_OK) << dl_last_error(c);
  double dt = 0.0;
  ASSERT_EQ(dl_time_step(c, &dt), DL_OK);
  EXPECT_EQ(dt, kDt);
  const std::string report = dl_compile_report(c);
  EXPECT_NE(report.find("end step: none"), std::string::npos) << report;
  EXPECT_NE(report.find("paddle (rigid_body) remote: every 100 steps"), std::string::npos) << report;

  int boxCount = 0;
  double boxOut[4];
  const auto exchangeAll = [&](int sample) {
    SCOPED_TRACE("sample " + std::to_string(sample));
    ASSERT_EQ(dl_simulation_box_exchange(c, box, nullptr, boxOut, &boxCount), DL_OK) << dl_last_error(c);
  };

  // Sample 0: the initial outputs; the bed is settled in place, the ball in the probe.
  exchangeAll(0);
  const int bedCount = boxCount - 1;
  ASSERT_GT(bedCount, 10);
  int probeCount = 0;
  double probeOut[7];
  ASSERT_EQ(dl_region_sensor_read(c, probe, &probeCount, probeOut), DL_OK) << dl_last_error(c);
  EXPECT_EQ(probeCount, 1);
  EXPECT_NEAR(probeOut[0], sphereMass(0.005), 1e-12);
  int counts3[3];
  double masses3[3];
  int counts2[2];
  double masses2[2];
  int counts4[4];
  double masses4[4];
  double wrench[12];
  const double twist[6] = {0, 0, 0, 0, 0, 0};
  std::vector<double> positions(150), radii(50);
  int listed = 0;
  const auto readRest = [&](int sample) {
    SCOPED_TRACE("sample " + std::to_string(sample));
    ASSERT_EQ(dl_particle_source_read(c, feed, counts3, masses3), DL_OK) << dl_last_error(c);
    ASSERT_EQ(dl_particle_sink_read(c, drain, counts2, masses2), DL_OK) << dl_last_error(c);
    ASSERT_EQ(dl_flow_sensor_read(c, gate, counts4, masses4), DL_OK) << dl_last_error(c);
    ASSERT_EQ(dl_particle_view_read(c, view, 50, positions.data(), radii.data(), &listed), DL_OK) << dl_last_error(c);
    ASSERT_EQ(dl_rigid_body_exchange(c, paddle, paddlePose, twist, wrench), DL_OK) << dl_last_error(c);
  };
  readRest(0);
  EXPECT_EQ(counts3[1], 0);
  EXPECT_EQ(counts2[1], 0);

  // Free fall of the ball for 10 samples (symplectic Euler: within g dt t of the closed form).
  for (int k = 1; k <= 10; ++k) {
    exchangeAll(k);
    ASSERT_EQ(dl_region_sensor_read(c, probe, &probeCount, probeOut), DL_OK) << dl_last_error(c);
    readRest(k);
  }
  const double t = 10 * kInterval;
  EXPECT_EQ(probeCount, 1);
  EXPECT_NEAR(probeOut[3], ballStart[2] - 0.5 * kG * t * t, kG * kDt * t) << "ball height";
  EXPECT_NEAR(probeOut[6], -kG * t, 1e-9) << "ball velocity";
  EXPECT_NEAR(boxOut[0], t, 1e-12);
  // The source: 4000/s over 10 ms within one particle, each of its mass.
  EXPECT_NEAR(counts3[1], 4000.0 * t, 1.0);
  EXPECT_NEAR(masses3[1], counts3[1] * sphereMass(0.002), 1e-12);
  EXPECT_EQ(boxCount, bedCount + 1 + counts3[1]);
  // The view lists at most 50 particles, each with a radius of one of the three kinds.
  EXPECT_GT(listed, 0);
  EXPECT_LE(listed, 50);
  for (int i = 0; i < std::min(listed, 50); ++i) {
    const double r = radii[static_cast<std::size_t>(i)];
    EXPECT_TRUE(std::abs(r - 0.004) < 1e-6 || std::abs(r - 0.002) < 1e-6 || std::abs(r - 0.005) < 1e-6) << r;
  }
  // The paddle (the server's STL) is far from every particle: no force on it; LAGGED, it
  // stands exactly on the pose sent.
  for (double w : wrench) EXPECT_EQ(w, 0.0);
  dl_package* outputs = dl_package_create();
  ASSERT_EQ(dl_get_outputs(c, paddle, outputs), DL_OK) << dl_last_error(c);
  double bodyOut[19];
  int n = 0;
  ASSERT_EQ(dl_get_reals(outputs, bodyOut, 19, &n), DL_OK);
  dl_package_destroy(outputs);
  for (int k = 0; k < 7; ++k) EXPECT_EQ(bodyOut[12 + k], paddlePose[k]) << "pose " << k;

  // Run-time inputs, sent with the packages of sample 11 (the calls of sample 10 already
  // sent theirs): the source off, the sink onto the ball, the probe moved into the bed.
  ASSERT_EQ(dl_particle_source_set_enabled(c, feed, 0), DL_OK) << dl_last_error(c);
  const double ballNow[3] = {probeOut[1], probeOut[2], probeOut[3]};
  ASSERT_EQ(dl_particle_sink_move(c, drain, ballNow), DL_OK) << dl_last_error(c);
  const double bedCentre[3] = {0.0, 0.0, 0.0};  // with radius 0.075 m: the bed, none of the fed particles
  ASSERT_EQ(dl_region_sensor_set_region(c, probe, bedCentre, nullptr, nullptr, 0.075), DL_OK) << dl_last_error(c);
  int fedBefore = 0;
  for (int k = 11; k <= 30; ++k) {
    exchangeAll(k);
    ASSERT_EQ(dl_region_sensor_read(c, probe, &probeCount, probeOut), DL_OK) << dl_last_error(c);
    readRest(k);
    if (k == 11) {
      fedBefore = counts3[1];  // the interval (10, 11] still ran with the source on
      continue;
    }
    EXPECT_EQ(counts3[0], 0) << "an off source inserts nothing, sample " << k;
    EXPECT_EQ(counts3[1], fedBefore);
  }
  EXPECT_NEAR(fedBefore, 4000.0 * 11 * kInterval, 1.0);
  EXPECT_EQ(counts2[1], 1) << "the sink removed the ball";
  EXPECT_NEAR(masses2[1], sphereMass(0.005), 1e-12);
  EXPECT_EQ(probeCount, bedCount) << "the moved probe holds the bed";
  // Every fed particle crosses the gate downwards (2 m/s over at most 0.025 m: within
  // 12.5 ms of its insertion, all by 23.5 ms < 30 ms); none upwards.
  EXPECT_EQ(counts4[3], fedBefore) << "negative total";
  EXPECT_EQ(counts4[2], 0) << "positive total";
  EXPECT_NEAR(masses4[3], fedBefore * sphereMass(0.002), 1e-12);

  EXPECT_EQ(dl_finish(c, "tool finished"), DL_OK);
  EXPECT_EQ(dl_wait_finished(c), DL_OK) << dl_last_error(c);
  EXPECT_STREQ(dl_finished_reason(c), "said Bye");
  EXPECT_EQ(server_->child.waitForExit(std::chrono::seconds(20)), 0) << "--once: the server exits after the run";
}

// The typed speed/accuracy declaration and the frame's motion as an input: in a frame
// accelerating upwards at a [m/s^2] with no gravity, a free particle accelerates at -a;
// the frame's acceleration reversed at run time brings its velocity back to zero. The view
// reports the particle by id with its velocity.
TEST_F(CAbiRealServer, SettingsDeclarationAndFrameMotionInput) {
  ASSERT_GT(server_->port, 0) << server_->announced;
  ClientGuard g;
  dl_client* c = g.client;
  ASSERT_EQ(dl_connect_to_host(c, server_->host.c_str(), server_->port, "site", nullptr), DL_OK) << dl_last_error(c);
  const double nan = std::nan("");
  const double zero[3] = {0.0, 0.0, 0.0};
  constexpr double kA = 5.0;  // [m/s^2]
  const double frame[12] = {0.0, 0.0, kA, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  int box = -1, glass = -1, ball = -1, probe = -1, view = -1;
  ASSERT_EQ(dl_declare_simulation_box_ex(c, "box", kInterval, kDt, nan, zero, nullptr, nullptr, 2, 1, 3.0, 0.05, 0.0, 1,
                                         frame, &box),
            DL_OK)
      << dl_last_error(c);
  EXPECT_EQ(dl_declare_simulation_box_ex(c, "box2", kInterval, kDt, nan, zero, nullptr, nullptr, 3, 1, nan, nan, nan, -1,
                                         nullptr, &box),
            DL_ERR_ARGUMENT)
      << "contact model 3 does not exist";
  ASSERT_EQ(dl_declare_material(c, "glass", "", kDensity, 5e6, 0.3, 0.5, 0.5, 0.0, &glass), DL_OK);
  ASSERT_EQ(dl_declare_single_particle(c, "ball", "glass", zero, zero, 0.01, &ball), DL_OK) << dl_last_error(c);
  ASSERT_EQ(dl_declare_region_sensor_sphere(c, "probe", kInterval, zero, 1.0, "", &probe), DL_OK);
  ASSERT_EQ(dl_declare_particle_view(c, "view", kInterval, 10, &view), DL_OK);
  ASSERT_EQ(dl_declarations_done(c), DL_OK) << dl_last_error(c);

  int count = 0;
  double out[7];
  double boxOut[4];
  double position[3], velocity[3], radius = 0.0;
  uint64_t id = 0;
  int listed = 0;
  const auto sample = [&] {
    ASSERT_EQ(dl_simulation_box_exchange(c, box, nullptr, boxOut, &count), DL_OK) << dl_last_error(c);
    ASSERT_EQ(dl_region_sensor_read(c, probe, &count, out), DL_OK) << dl_last_error(c);
    ASSERT_EQ(dl_particle_view_read_ex(c, view, 1, position, velocity, &radius, &id, &listed), DL_OK)
        << dl_last_error(c);
  };
  for (int k = 0; k <= 10; ++k) sample();
  const double t = 10 * kInterval;
  EXPECT_NEAR(out[6], -kA * t, 1e-9) << "v_z = -a t";
  EXPECT_EQ(listed, 1);
  EXPECT_EQ(id, 1u);
  EXPECT_FLOAT_EQ(static_cast<float>(velocity[2]), static_cast<float>(out[6]));
  EXPECT_FLOAT_EQ(static_cast<float>(radius), 0.005F);

  const double down[3] = {0.0, 0.0, -kA};
  ASSERT_EQ(dl_simulation_box_set_frame(c, box, down, zero, zero, nullptr), DL_OK) << dl_last_error(c);
  // Sent with the box's package of sample 11 (the call for sample 10 already sent its
  // package): -a over 11 ms, then +a over 11 ms.
  for (int k = 11; k <= 22; ++k) sample();
  EXPECT_NEAR(out[6], 0.0, 1e-9) << "the reversed acceleration took the velocity back";
  EXPECT_EQ(dl_finish(c, "done"), DL_OK);
  EXPECT_EQ(server_->child.waitForExit(std::chrono::seconds(20)), 0);
}

// The general source declaration: a disc region with a discrete size distribution and a
// box with a truncated normal one. Without gravity the inserted grains stay where they were
// placed, so every one must lie inside its region (radius - r of the axis, |axial| <=
// thickness / 2 - r), have one of the declared radii (or one within [r_min, r_max]), and the
// source's reported mass must be the sum of their sphere masses. The view reports single
// precision: radii and positions are compared within 1e-7 m, masses within 1e-6.
TEST_F(CAbiRealServer, SourceWithADiscRegionAndSizeDistributions) {
  ASSERT_GT(server_->port, 0) << server_->announced;
  ClientGuard g;
  dl_client* c = g.client;
  ASSERT_EQ(dl_connect_to_host(c, server_->host.c_str(), server_->port, "sources", nullptr), DL_OK) << dl_last_error(c);
  const double nan = std::nan("");
  const double zero[3] = {0.0, 0.0, 0.0};
  const double lower[3] = {-0.2, -0.2, -0.2};
  const double upper[3] = {0.2, 0.2, 0.2};
  int box = -1, glass = -1, disc = -1, cube = -1, view = -1;
  ASSERT_EQ(dl_declare_simulation_box(c, "box", kInterval, kDt, nan, zero, lower, upper, 0, &box), DL_OK)
      << dl_last_error(c);
  ASSERT_EQ(dl_declare_material(c, "glass", "", kDensity, 5e6, 0.3, 0.5, 0.5, 0.0, &glass), DL_OK) << dl_last_error(c);
  constexpr double kDiscRadius = 0.05, kThickness = 0.02, kDiscZ = 0.1;  // [m]
  const double discRegion[8] = {0.0, 0.0, kDiscZ, 0.0, 0.0, 1.0, kDiscRadius, kThickness};
  const double discrete[4] = {0.003, 1.0, 0.005, 3.0};
  ASSERT_EQ(dl_declare_particle_source(c, "disc", kInterval, "glass", 1, discRegion, 4, discrete, 4, 5000.0, -1.0,
                                       nullptr, 11, &disc),
            DL_OK)
      << dl_last_error(c);
  const double cubeRegion[6] = {0.0, 0.0, -0.1, 0.04, 0.04, 0.04};
  const double normal[4] = {0.004, 0.001, 0.003, 0.005};
  ASSERT_EQ(dl_declare_particle_source(c, "cube", kInterval, "glass", 0, cubeRegion, 3, normal, 4, 5000.0, -1.0,
                                       nullptr, 12, &cube),
            DL_OK)
      << dl_last_error(c);
  int bad = -1;
  EXPECT_EQ(dl_declare_particle_source(c, "odd", kInterval, "glass", 1, discRegion, 4, discrete, 3, 1.0, -1.0, nullptr,
                                       1, &bad),
            DL_ERR_ARGUMENT)
      << "discrete sizes come in (radius, weight) pairs";
  EXPECT_EQ(dl_declare_particle_source(c, "cone", kInterval, "glass", 2, discRegion, 0, discrete, 1, 1.0, -1.0, nullptr,
                                       1, &bad),
            DL_ERR_ARGUMENT)
      << "region 2 does not exist";
  ASSERT_EQ(dl_declare_particle_view(c, "view", kInterval, 1000, &view), DL_OK) << dl_last_error(c);
  ASSERT_EQ(dl_declarations_done(c), DL_OK) << dl_last_error(c);

  int count = 0;
  double boxOut[4];
  int discCounts[3], cubeCounts[3];
  double discMasses[3], cubeMasses[3];
  std::vector<double> positions(3000), radii(1000);
  int listed = 0;
  for (int k = 0; k <= 10; ++k) {
    SCOPED_TRACE("sample " + std::to_string(k));
    ASSERT_EQ(dl_simulation_box_exchange(c, box, nullptr, boxOut, &count), DL_OK) << dl_last_error(c);
    ASSERT_EQ(dl_particle_source_read(c, disc, discCounts, discMasses), DL_OK) << dl_last_error(c);
    ASSERT_EQ(dl_particle_source_read(c, cube, cubeCounts, cubeMasses), DL_OK) << dl_last_error(c);
    ASSERT_EQ(dl_particle_view_read(c, view, 1000, positions.data(), radii.data(), &listed), DL_OK)
        << dl_last_error(c);
  }
  // 5000 per second each for 10 ms: 50 grains per source, all placed.
  EXPECT_NEAR(discCounts[1], 50, 1);
  EXPECT_NEAR(cubeCounts[1], 50, 1);
  EXPECT_EQ(discCounts[2] + cubeCounts[2], 0) << "no shortfall";
  ASSERT_EQ(listed, discCounts[1] + cubeCounts[1]);
  double discMass = 0.0, cubeMass = 0.0;
  int small = 0;
  constexpr double kTol = 1e-7;  // [m], a float's resolution at 0.1 m
  const auto near = [](double a, double b) { return std::abs(a - b) < 1e-9; };
  for (int i = 0; i < listed; ++i) {
    const double x = positions[3 * i], y = positions[3 * i + 1], z = positions[3 * i + 2], r = radii[i];
    SCOPED_TRACE("grain " + std::to_string(i) + " r = " + std::to_string(r));
    if (z > 0.0) {
      EXPECT_TRUE(near(r, 0.003) || near(r, 0.005));
      EXPECT_LE(std::hypot(x, y), kDiscRadius - r + kTol);
      EXPECT_LE(std::abs(z - kDiscZ), kThickness / 2 - r + kTol);
      small += near(r, 0.003) ? 1 : 0;
      discMass += sphereMass(r);
    } else {
      EXPECT_GE(r, 0.003 - 1e-9);
      EXPECT_LE(r, 0.005 + 1e-9);
      EXPECT_LE(std::max({std::abs(x), std::abs(y), std::abs(z + 0.1)}), 0.04 - r + kTol);
      cubeMass += sphereMass(r);
    }
  }
  EXPECT_NEAR(discMasses[1], discMass, 1e-6 * discMass);
  EXPECT_NEAR(cubeMasses[1], cubeMass, 1e-6 * cubeMass);
  // Weights 1 : 3, so a quarter are small: binomial(50, 1/4) has a standard deviation of 3.1.
  EXPECT_NEAR(small, discCounts[1] / 4.0, 4 * 3.1);
  EXPECT_EQ(dl_finish(c, "done"), DL_OK);
  EXPECT_EQ(server_->child.waitForExit(std::chrono::seconds(20)), 0);
}

// A pit whose clods are joined by parallel bonds, both declared with the typed calls; a
// region sensor over the bed reads the bonds (dl_region_sensor_read_bonds).
TEST_F(CAbiRealServer, ParallelBondsAndClodsDeclaredThroughTheCAbiAreCounted) {
  ASSERT_GT(server_->port, 0) << server_->announced;
  ClientGuard g;
  dl_client* c = g.client;
  ASSERT_EQ(dl_connect_to_host(c, server_->host.c_str(), server_->port, "bonds", nullptr), DL_OK) << dl_last_error(c);
  const double nan = std::nan("");
  const double gravity[3] = {0.0, 0.0, -kG};
  const double lower[3] = {-0.1, -0.1, -0.05};
  const double upper[3] = {0.1, 0.1, 0.2};
  int box = -1, glass = -1, floor = -1, bed = -1, clay = -1, probe = -1;
  // The box is declared only (interval 0): the probe is the one exchanged component.
  ASSERT_EQ(dl_declare_simulation_box(c, "box", 0.0, kDt, nan, gravity, lower, upper, 0, &box), DL_OK)
      << dl_last_error(c);
  ASSERT_EQ(dl_declare_material(c, "glass", "", kDensity, 5e6, 0.3, 0.5, 0.5, 0.0, &glass), DL_OK) << dl_last_error(c);
  const double origin[3] = {0.0, 0.0, 0.0};
  const double up[3] = {0.0, 0.0, 1.0};
  ASSERT_EQ(dl_declare_plane(c, "floor", origin, up, "glass", &floor), DL_OK) << dl_last_error(c);
  const double bedLower[3] = {-0.05, -0.05, 0.0};
  const double bedUpper[3] = {0.05, 0.05, 0.05};
  const double clods[2] = {0.4, 0.012};  // fraction [-], radius [m]
  ASSERT_EQ(dl_declare_pit_generator_clods(c, "bed", "glass", bedLower, bedUpper, 0.004, 0.004, 0.012, 7, clods, "clay",
                                           &bed),
            DL_OK)
      << dl_last_error(c);
  int bad = -1;
  EXPECT_EQ(dl_declare_parallel_bonds(c, "odd", nullptr, nullptr, "", 0, &bad), DL_ERR_ARGUMENT);
  const double properties[8] = {1e8, 1e8, 1e6, 1e6, 4e-4, nan, 0.0, nan};
  ASSERT_EQ(dl_declare_parallel_bonds(c, "clay", properties, nullptr, "glass", 0, &clay), DL_OK) << dl_last_error(c);
  const double centre[3] = {0.0, 0.0, 0.025};
  const double size[3] = {0.2, 0.2, 0.1};
  ASSERT_EQ(dl_declare_region_sensor_box(c, "probe", kInterval, centre, size, "", &probe), DL_OK) << dl_last_error(c);
  ASSERT_EQ(dl_declarations_done(c), DL_OK) << dl_last_error(c);

  int count = 0;
  double out[7];
  int bonds[2] = {-1, -1};
  for (int k = 0; k < 2; ++k) {
    ASSERT_EQ(dl_region_sensor_read_bonds(c, probe, &count, out, bonds), DL_OK) << dl_last_error(c);
    std::printf("read %d: %d spheres, bonds %d intact, %d broken\n", k, count, bonds[0], bonds[1]);
    // Receive first: the first read returns the initial state, before the bonds are made.
    if (k == 0) {
      EXPECT_EQ(bonds[0], 0);
    }
  }
  EXPECT_GT(count, 20);
  EXPECT_GT(bonds[0], 0) << "the clods are bonded at the first step";
  EXPECT_EQ(bonds[1], 0) << "nothing loads them beyond their strength";
  EXPECT_EQ(dl_finish(c, "tool finished"), DL_OK);
  EXPECT_EQ(server_->child.waitForExit(std::chrono::seconds(20)), 0);
}

// Two rows of five touching spheres, each under a parallel-bond rule limited to a sphere
// around its second particle that holds the centres of the first three only: the typed call
// (dl_declare_parallel_bonds_region) on one row, the generic layout as the Modelica
// ParallelBonds fills it on the other. Each row has exactly its two pairs inside bonded
// (four without the region), counted by a region sensor over the row.
TEST_F(CAbiRealServer, ASphereLimitedBondRuleBondsOnlyThePairsInsideIt) {
  ASSERT_GT(server_->port, 0) << server_->announced;
  ClientGuard g;
  dl_client* c = g.client;
  ASSERT_EQ(dl_connect_to_host(c, server_->host.c_str(), server_->port, "bond_regions", nullptr), DL_OK)
      << dl_last_error(c);
  const double nan = std::nan("");
  const double none[3] = {0.0, 0.0, 0.0};
  const double lower[3] = {-0.1, -0.1, -0.1};
  const double upper[3] = {0.1, 0.1, 0.1};
  int handle = -1;
  ASSERT_EQ(dl_declare_simulation_box(c, "box", 0.0, kDt, nan, none, lower, upper, 0, &handle), DL_OK)
      << dl_last_error(c);
  ASSERT_EQ(dl_declare_material(c, "glass", "", kDensity, 5e6, 0.3, 0.5, 0.5, 0.0, &handle), DL_OK) << dl_last_error(c);
  constexpr double kRadius = 0.005;     // [m]
  constexpr double kSpacing = 0.01001;  // centre distance: a 10 um gap [m]
  constexpr double kRows[2] = {0.0, 0.05};  // y of each row [m]
  for (int row = 0; row < 2; ++row) {
    for (int i = 0; i < 5; ++i) {
      char name[16];
      std::snprintf(name, sizeof name, "r%ds%d", row, i);
      const double position[3] = {kSpacing * (i - 2), kRows[row], 0.0};
      ASSERT_EQ(dl_declare_single_particle(c, name, "glass", position, none, 2.0 * kRadius, &handle), DL_OK)
          << dl_last_error(c);
    }
  }
  // Centred on the second sphere; 1.2 spacings holds the centres of the first three only.
  const double radius = 1.2 * kSpacing;
  const double properties[8] = {1e8, 1e8, 1e6, 1e6, 2e-5, nan, 0.0, nan};
  const double typedCentre[3] = {-kSpacing, kRows[0], 0.0};
  ASSERT_EQ(dl_declare_parallel_bonds_region(c, "typed", properties, DL_REGION_SPHERE, typedCentre, nullptr, nullptr,
                                             radius, "", "glass", 0, &handle),
            DL_OK)
      << dl_last_error(c);
  {
    dl_package* pkg = dl_package_create();
    const double reals[19] = {0.0, 1e8, 1e8, 1e6, 1e6, 2e-5, nan, 0.0, nan, -kSpacing, kRows[1], 0.0,
                              radius, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0};
    const long long ints[2] = {0, DL_REGION_SPHERE};
    const char* strings[4] = {"parallel_bonds", "generic", "", "glass"};
    ASSERT_EQ(dl_set_data(pkg, ints, 2, reals, 19, strings, 4), DL_OK);
    ASSERT_EQ(dl_send_package(c, pkg), DL_OK) << dl_last_error(c);
    dl_package_destroy(pkg);
  }
  int probes[2] = {-1, -1};
  const double size[3] = {0.08, 0.02, 0.02};
  for (int row = 0; row < 2; ++row) {
    const double centre[3] = {0.0, kRows[row], 0.0};
    char name[16];
    std::snprintf(name, sizeof name, "row%d", row);
    ASSERT_EQ(dl_declare_region_sensor_box(c, name, kInterval, centre, size, "", &probes[row]), DL_OK)
        << dl_last_error(c);
  }
  ASSERT_EQ(dl_declarations_done(c), DL_OK) << dl_last_error(c);

  int count = 0;
  double out[7];
  for (int k = 0; k < 2; ++k) {
    for (int row = 0; row < 2; ++row) {
      int bonds[2] = {-1, -1};
      ASSERT_EQ(dl_region_sensor_read_bonds(c, probes[row], &count, out, bonds), DL_OK) << dl_last_error(c);
      if (k == 0) continue;  // receive first: the initial state, before the bonds are made
      EXPECT_EQ(count, 5) << "row " << row;
      EXPECT_EQ(bonds[0], 2) << "row " << row << ": the two pairs inside the sphere, not the four of the row";
      EXPECT_EQ(bonds[1], 0) << "row " << row;
    }
  }
  EXPECT_EQ(dl_finish(c, "done"), DL_OK);
  EXPECT_EQ(server_->child.waitForExit(std::chrono::seconds(20)), 0);
}

TEST_F(CAbiRealServer, ARegionSensorMovingAtAConstantVelocityPassesThreeSpheres) {
  // Three spheres at rest 5 cm apart, no gravity; a sensor sphere declared through the
  // generic layout (as the Modelica RegionSensor fills it) starts 5 cm before the first and
  // moves at 5 m/s, so at each 10 ms reading it holds the next sphere alone. At t = 0 it
  // is empty: count 0 and zeros, never NaN.
  ASSERT_GT(server_->port, 0) << server_->announced;
  ClientGuard g;
  dl_client* c = g.client;
  ASSERT_EQ(dl_connect_to_host(c, server_->host.c_str(), server_->port, "moving_region", nullptr), DL_OK)
      << dl_last_error(c);
  const double nan = std::nan("");
  constexpr double kRadius = 0.005;   // [m]
  constexpr double kApart = 0.05;     // [m]
  constexpr double kSpeed = 5.0;      // [m/s]
  constexpr double kReading = 0.01;   // [s]: the sensor moves kApart per reading
  {
    dl_package* pkg = dl_package_create();
    // interval, centre, radius and two unused, orientation (not given), velocity
    const double reals[14] = {kReading, -kApart, 0.0, 0.0, 0.01, 0.0, 0.0, nan, nan, nan, nan, kSpeed, 0.0, 0.0};
    const long long ints[1] = {1};  // sphere
    const char* strings[3] = {"region_sensor", "scan", ""};
    ASSERT_EQ(dl_set_data(pkg, ints, 1, reals, 14, strings, 3), DL_OK);
    ASSERT_EQ(dl_send_package(c, pkg), DL_OK) << dl_last_error(c);
    dl_package_destroy(pkg);
  }
  const int sensor = 0;  // the handle of this client's first component
  const double none[3] = {0.0, 0.0, 0.0};
  const double lower[3] = {-0.2, -0.1, -0.1};
  const double upper[3] = {0.3, 0.1, 0.1};
  int handle = -1;
  ASSERT_EQ(dl_declare_simulation_box(c, "box", 0.0, kDt, nan, none, lower, upper, 0, &handle), DL_OK)
      << dl_last_error(c);
  ASSERT_EQ(dl_declare_material(c, "glass", "", kDensity, 5e6, 0.3, 0.5, 0.5, 0.0, &handle), DL_OK) << dl_last_error(c);
  for (int i = 0; i < 3; ++i) {
    char name[8];
    std::snprintf(name, sizeof name, "s%d", i);
    const double position[3] = {kApart * i, 0.0, 0.0};
    ASSERT_EQ(dl_declare_single_particle(c, name, "glass", position, none, 2.0 * kRadius, &handle), DL_OK)
        << dl_last_error(c);
  }
  ASSERT_EQ(dl_declarations_done(c), DL_OK) << dl_last_error(c);
  int count = -1;
  double out[7];
  ASSERT_EQ(dl_region_sensor_read(c, sensor, &count, out), DL_OK) << dl_last_error(c);
  EXPECT_EQ(count, 0) << "t = 0: the region is 5 cm before the first sphere";
  for (const double value : out) EXPECT_EQ(value, 0.0) << "an empty region reads zeros";
  for (int k = 1; k <= 3; ++k) {
    ASSERT_EQ(dl_region_sensor_read(c, sensor, &count, out), DL_OK) << dl_last_error(c);
    EXPECT_EQ(count, 1) << "reading " << k;
    EXPECT_NEAR(out[0], sphereMass(kRadius), 1e-12 * sphereMass(kRadius)) << "reading " << k;
    EXPECT_NEAR(out[1], kApart * (k - 1), 1e-9) << "reading " << k << ": the centre of sphere " << k - 1;
  }
  EXPECT_EQ(dl_finish(c, "done"), DL_OK);
  EXPECT_EQ(server_->child.waitForExit(std::chrono::seconds(20)), 0);
}

}  // namespace
}  // namespace demlink::integration
