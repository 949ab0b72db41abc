#include "study_coupling.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "demlink/core/walls/coupled_motion.hpp"
#include "demlink/core/walls/mesh_body.hpp"

namespace demlink::study {
namespace {

using core::Vec3;
using core::World;
using Clock = std::chrono::steady_clock;

constexpr double kSide = 0.05;       ///< box side [m]
constexpr double kPlateHalf = 0.015; ///< plate half side [m]
constexpr double kPlateHalfThickness = 0.002;  ///< [m]
constexpr double kParkingHeight = 1.0;  ///< plate reference height while the bed settles [m]

/// The bed world with the plate parked far above it (same structure for every case, so a
/// checkpoint of the settled bed restores into it).
World bedWorld(const Knobs& knobs, std::size_t grains) {
  World world(studySettings(knobs));
  world.addMaterial(studyMaterial(knobs));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0});
  world.addPlane({"x0", Vec3::Zero(), Vec3::UnitX(), 0});
  world.addPlane({"x1", Vec3::Constant(kSide), -Vec3::UnitX(), 0});
  world.addPlane({"y0", Vec3::Zero(), Vec3::UnitY(), 0});
  world.addPlane({"y1", Vec3::Constant(kSide), -Vec3::UnitY(), 0});
  core::TriangleMesh plate = core::axisAlignedBoxMesh(Vec3(-kPlateHalf, -kPlateHalf, -kPlateHalfThickness),
                                                      Vec3(kPlateHalf, kPlateHalf, kPlateHalfThickness));
  world.addMesh(core::MeshBody("plate", std::move(plate.vertices), std::move(plate.triangles), 0));
  world.mesh(0).setPose(Vec3(0.5 * kSide, 0.5 * kSide, kParkingHeight), core::Quat::Identity());
  addLattice(world, grains, parcelRadius(knobs), parcelRadiusMax(knobs), Vec3::Zero(), Vec3(kSide, kSide, 0.0), knobs.seed);
  return world;
}

/// Height of the bed's surface under the plate: the highest sphere top below its
/// footprint, so that the plate starts clear of every grain [m].
double surfaceHeight(const core::ParticleArrays& p) {
  double top = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& x = p.position[i];
    if (std::abs(x.x() - 0.5 * kSide) < kPlateHalf + p.radius[i] &&
        std::abs(x.y() - 0.5 * kSide) < kPlateHalf + p.radius[i]) {
      top = std::max(top, x.z() + p.radius[i]);
    }
  }
  return top;
}

CouplingResult runCase(const Knobs& knobs, std::size_t grains, const std::string& settled, double surface,
                       double duration, const CouplingCase& c, double cpuLimit) {
  CouplingResult out(c);
  const auto start = Clock::now();
  World world = bedWorld(knobs, grains);
  world.restoreCheckpoint(std::string_view(settled), "settled bed");
  const double dt = world.settings().time_step;
  const double interval = static_cast<double>(c.interval_steps) * dt;
  out.interval = interval;
  const double g = world.state().gravity.z();
  core::CoupledMotion motion(0, core::MotionMode::Predicted);
  // Client state: the plate's reference height and vertical speed; it starts at rest 1 mm
  // above the surface.
  double z = surface + kPlateHalfThickness + 0.001;
  double v = 0.0;
  world.mesh(0).setPose(Vec3(0.5 * kSide, 0.5 * kSide, z), core::Quat::Identity());
  double heldForce = 0.0;  // the force of the interval that ended (ReceiveFirst)
  const double t0 = world.time();
  std::vector<double> heights;
  SceneResult cost;
  while (world.time() < t0 + duration - 0.5 * dt) {
    const core::RigidPose pose{Vec3(0.5 * kSide, 0.5 * kSide, z), core::Quat::Identity()};
    core::MeshBody& mesh = world.mesh(motion.meshIndex());
    motion.beginInterval(mesh, dt, pose, core::RigidTwist{Vec3(0.0, 0.0, v), Vec3::Zero()}, c.interval_steps);
    advance(world, world.time() + interval, cost, cpuLimit, [&] { motion.afterStep(mesh, dt); });
    const double received = motion.endInterval(mesh, dt).mean_force.z();
    const double force = c.order == ClientOrder::SendFirst ? received : heldForce;
    heldForce = received;
    const double a = force / c.mass + g;
    z += v * interval + 0.5 * a * interval * interval;
    v += a * interval;
    if (!std::isfinite(z) || std::abs(z - surface) > 0.1) {
      out.status = "unstable: plate left the bed";
      break;
    }
    heights.push_back(z);
  }
  if (out.status == "ok") {
    const std::size_t from = heights.size() - heights.size() / 4;
    double mean = 0.0;
    for (std::size_t i = from; i < heights.size(); ++i) mean += heights[i];
    mean /= static_cast<double>(heights.size() - from);
    double variance = 0.0;
    for (std::size_t i = from; i < heights.size(); ++i) variance += (heights[i] - mean) * (heights[i] - mean);
    out.oscillation = std::sqrt(variance / static_cast<double>(heights.size() - from));
    out.depth = surface - (mean - kPlateHalfThickness);
  }
  out.wall = std::chrono::duration<double>(Clock::now() - start).count();
  out.simulated = world.time() - t0;
  out.particle_steps = cost.particle_steps;
  return out;
}

}  // namespace

const char* toString(ClientOrder order) {
  return order == ClientOrder::SendFirst ? "send_first" : "receive_first";
}

std::vector<CouplingResult> runCoupling(const Knobs& knobs, std::size_t grains, double settle, double duration,
                                        const std::vector<CouplingCase>& cases, double cpuLimit,
                                        const std::function<void(const CouplingResult&)>& done) {
  World world = bedWorld(knobs, grains);
  world.initialize();
  SceneResult cost;
  advance(world, settle, cost, cpuLimit);
  const double surface = surfaceHeight(world.particles());
  std::ostringstream settled;
  world.saveCheckpoint(settled);
  std::vector<CouplingResult> results;
  for (const CouplingCase& c : cases) {
    try {
      results.push_back(runCase(knobs, grains, settled.str(), surface, duration, c, cpuLimit));
    } catch (const std::exception& error) {
      CouplingResult failed(c);
      failed.status = std::string("broke: ") + error.what();
      results.push_back(failed);
    }
    if (done) done(results.back());
  }
  return results;
}

}  // namespace demlink::study
