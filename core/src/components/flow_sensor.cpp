/// Flow sensor (contract and method in flow_sensor.hpp).
///
/// The segment test is done in the surface's frame at each observation, so a moving
/// surface sees the relative motion: before = previous local position (in the frame of
/// the previous step), after = current local position. The crossing point is
/// q = a + t (b - a) with t = a_z / (a_z - b_z), well defined because the sides differ.
#include "demlink/core/components/flow_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "demlink/core/components/component_state.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/components/component_world.hpp"

namespace demlink::core {

FlowSensor::FlowSensor(std::string name, SurfaceShape shape, RegionPlacement placement, SampleSchedule schedule,
                       std::string fieldPrefix)
    : SampledComponent(std::move(name), schedule, std::move(fieldPrefix)),
      shape_(shape),
      placement_(std::move(placement)) {
  placement_.validate(this->fieldPrefix() + ".surface");
}

void FlowSensor::initialize(ComponentWorld& world) {
  placement_.resolve(world.meshes().size(), fieldPrefix() + ".surface");
  resolveSchedule(world);
  previous_.clear();
  band_ = 0.0;
  scan(world, false);  // sizes the band from the initial velocities
  scan(world, false);  // remembers the particles within it
  publish(world, {world.time(), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0});
}

void FlowSensor::observe(const ComponentWorld& world) {
  scan(world, true);
  if (!sampleDue(world)) return;
  last_interval_ = since_sample_;
  since_sample_ = {};
  const FlowTally& i = last_interval_;
  const FlowTally& t = total_;
  publish(world, {world.time(), static_cast<double>(i.positive_count), static_cast<double>(i.negative_count),
           static_cast<double>(i.netCount()), i.positive_mass, i.negative_mass, i.netMass(),
           static_cast<double>(t.positive_count), static_cast<double>(t.negative_count),
           static_cast<double>(t.netCount()), t.positive_mass, t.negative_mass, t.netMass()});
}

void FlowSensor::scan(const ComponentWorld& world, bool count) {
  const RegionPose pose = placement_.poseAt(world.meshes(), world.time());
  const Vec3 normal = pose.rotation.col(2);
  const double reach = shape_.boundingRadius() + band_;  // in-plane distance that can matter [m]
  const ParticleArrays& p = world.particles();
  current_.clear();
  double fastest = 0.0;  // largest squared speed [m^2/s^2]
  double largest = 0.0;  // largest radius [m]
  for (std::size_t i = 0; i < p.size(); ++i) {
    fastest = std::max(fastest, p.velocity[i].squaredNorm());
    largest = std::max(largest, p.radius[i]);
    const Vec3 offset = p.position[i] - pose.centre;
    const double height = normal.dot(offset);
    if (std::abs(height) > band_ || (offset - height * normal).squaredNorm() > reach * reach) continue;
    const Vec3 local = pose.rotation.transpose() * offset;
    if (count) {
      const auto before = previous_.find(p.id[i]);
      if (before != previous_.end()) countCrossing(before->second, local, p.mass[i]);
    }
    current_.emplace(p.id[i], local);
  }
  std::swap(previous_, current_);
  const double dt = world.settings().time_step * static_cast<double>(observation_spacing_);  // between observations
  const double speed = std::sqrt(fastest) + placement_.speedBound(world.meshes(), world.time(), shape_.boundingRadius());
  band_ = std::max(0.5 * largest, 4.0 * speed * dt + world.settings().gravity.norm() * dt * dt);
}

void FlowSensor::countCrossing(const Vec3& before, const Vec3& after, double mass) {
  const bool wasAbove = before.z() > 0.0;
  const bool isAbove = after.z() > 0.0;
  if (wasAbove == isAbove) return;
  const double t = before.z() / (before.z() - after.z());
  const Vec3 crossing = before + t * (after - before);
  if (!shape_.containsInPlane(crossing.x(), crossing.y())) return;
  FlowTally* tallies[2] = {&total_, &since_sample_};
  for (FlowTally* tally : tallies) {
    if (isAbove) {
      ++tally->positive_count;
      tally->positive_mass += mass;
    } else {
      ++tally->negative_count;
      tally->negative_mass += mass;
    }
  }
}

namespace {

void writeFlowTally(StateWriter& out, const FlowTally& tally) {
  out.write(tally.positive_count);
  out.write(tally.negative_count);
  out.write(tally.positive_mass);
  out.write(tally.negative_mass);
}

FlowTally readFlowTally(StateReader& in, const std::string& what) {
  FlowTally tally;
  tally.positive_count = in.read<std::uint64_t>();
  tally.negative_count = in.read<std::uint64_t>();
  tally.positive_mass = readNonNegative(in, what + " positive mass");
  tally.negative_mass = readNonNegative(in, what + " negative mass");
  return tally;
}

}  // namespace

void FlowSensor::saveState(StateWriter& out) const {
  SampledComponent::saveState(out);
  const std::size_t section = out.beginSection("FLOW");
  out.write(band_);
  writeFlowTally(out, total_);
  writeFlowTally(out, since_sample_);
  writeFlowTally(out, last_interval_);
  std::vector<std::pair<std::uint64_t, Vec3>> remembered(previous_.begin(), previous_.end());
  std::sort(remembered.begin(), remembered.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  out.write<std::uint64_t>(remembered.size());
  for (const auto& [id, local] : remembered) {
    out.write(id);
    out.write(local);
  }
  out.endSection(section);
}

void FlowSensor::loadState(StateReader& in) {
  SampledComponent::loadState(in);
  StateReader s = componentSection(in, "FLOW", "crossings");
  const double band = readNonNegative(s, "band half-width");
  const FlowTally total = readFlowTally(s, "total");
  const FlowTally since = readFlowTally(s, "since the last sample");
  const FlowTally last = readFlowTally(s, "last interval");
  const auto count = s.read<std::uint64_t>();
  s.requireAvailable(count, sizeof(std::uint64_t) + StateCodec<Vec3>::kBytes, "remembered particle count");
  std::unordered_map<std::uint64_t, Vec3> previous;
  previous.reserve(static_cast<std::size_t>(count));
  std::uint64_t lastId = 0;
  for (std::uint64_t k = 0; k < count; ++k) {
    const auto id = s.read<std::uint64_t>();
    if (k > 0 && id <= lastId) s.fail(std::to_string(id), "remembered particle ids not strictly increasing");
    lastId = id;
    previous.emplace(id, readFiniteVector(s, "remembered position of particle " + std::to_string(id)));
  }
  s.requireEnd();
  band_ = band;
  total_ = total;
  since_sample_ = since;
  last_interval_ = last;
  previous_ = std::move(previous);
  current_.clear();
}

std::vector<std::string> FlowSensor::columns() const {
  return {"time_s",
          "positive_interval",
          "negative_interval",
          "net_interval",
          "positive_mass_interval_kg",
          "negative_mass_interval_kg",
          "net_mass_interval_kg",
          "positive_total",
          "negative_total",
          "net_total",
          "positive_mass_total_kg",
          "negative_mass_total_kg",
          "net_mass_total_kg"};
}

}  // namespace demlink::core
