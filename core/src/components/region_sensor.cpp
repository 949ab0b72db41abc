/// Region sensor (contract in region_sensor.hpp).
///
/// One pass over the particles at each sample (not every step): transform the centre
/// into the region's frame, test membership, accumulate m, m v and m x in slot order
/// (deterministic for a given slot order); then one pass over the bonds, testing each
/// bond's midpoint.
#include "demlink/core/components/region_sensor.hpp"

#include <cmath>
#include <limits>

#include "demlink/core/components/component_state.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/components/component_world.hpp"

namespace demlink::core {
namespace {

/// An empty region's mean velocity and centre of mass: missing (NaN in memory, an empty
/// CSV cell; a client is sent no value).
Vec3 emptyRegionMean() { return Vec3::Constant(std::numeric_limits<double>::quiet_NaN()); }

}  // namespace

RegionSensor::RegionSensor(std::string name, VolumeShape shape, RegionPlacement placement, SampleSchedule schedule,
                           std::string fieldPrefix)
    : SampledComponent(std::move(name), schedule, std::move(fieldPrefix)),
      shape_(shape),
      placement_(std::move(placement)) {
  placement_.validate(this->fieldPrefix() + ".region");
}

void RegionSensor::initialize(ComponentWorld& world) {
  placement_.resolve(world.meshes().size(), fieldPrefix() + ".region");
  resolveSchedule(world);
  counts_bonds_ = world.bonds().hasRules();
  sample(world);
}

void RegionSensor::changeRegion(const ComponentWorld& world, const RegionChange& change, const std::string& fieldPrefix) {
  applyRegionChange(change, world.time(), shape_, placement_, fieldPrefix);
  inputs_changed_ = true;
}

void RegionSensor::saveInputs(StateWriter& out) const {
  const std::size_t section = out.beginSection("RGNI");
  writeRegionInputs(out, shape_, placement_);
  out.endSection(section);
}

void RegionSensor::loadInputs(StateReader& in) {
  StateReader s = componentSection(in, "RGNI", "region_inputs");
  readRegionInputs(s, shape_, placement_);
  s.requireEnd();
  inputs_changed_ = true;
}

void RegionSensor::observe(const ComponentWorld& world) {
  if (sampleDue(world)) sample(world);
}

RegionReading RegionSensor::measure(const ComponentWorld& world) const {
  const RegionPose pose = placement_.poseAt(world.meshes(), world.time());
  const ParticleArrays& p = world.particles();
  RegionReading reading;
  reading.time = world.time();
  Vec3 momentum = Vec3::Zero();  // [kg m/s]
  Vec3 moment = Vec3::Zero();    // [kg m]
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!shape_.contains(pose, p.position[i])) continue;
    ++reading.count;
    reading.mass += p.mass[i];
    momentum += p.mass[i] * p.velocity[i];
    moment += p.mass[i] * p.position[i];
  }
  if (reading.count == 0) {
    reading.mean_velocity = reading.centre_of_mass = emptyRegionMean();
  } else {
    reading.mean_velocity = momentum / reading.mass;
    reading.centre_of_mass = moment / reading.mass;
  }
  for (const ParallelBond& bond : world.bonds().bonds()) {
    if (!shape_.contains(pose, 0.5 * (p.position[bond.slot_a] + p.position[bond.slot_b]))) continue;
    ++(bond.broken ? reading.bonds_broken : reading.bonds_intact);
  }
  return reading;
}

void RegionSensor::sample(const ComponentWorld& world) {
  latest_ = measure(world);
  const RegionReading& r = latest_;
  std::vector<double> row{r.time,
                          static_cast<double>(r.count),
                          r.mass,
                          r.mean_velocity.x(),
                          r.mean_velocity.y(),
                          r.mean_velocity.z(),
                          r.centre_of_mass.x(),
                          r.centre_of_mass.y(),
                          r.centre_of_mass.z()};
  if (counts_bonds_) row.insert(row.end(), {static_cast<double>(r.bonds_intact), static_cast<double>(r.bonds_broken)});
  publish(world, std::move(row));
}

void RegionSensor::saveState(StateWriter& out) const {
  SampledComponent::saveState(out);
  const std::size_t section = out.beginSection("REGN");
  out.write(latest_.time);
  out.write(latest_.count);
  out.write(latest_.mass);
  // An empty region has no mean velocity or centre of mass (NaN in memory): zeros here,
  // told apart by the count.
  const bool empty = latest_.count == 0;
  out.write(empty ? Vec3(Vec3::Zero()) : latest_.mean_velocity);
  out.write(empty ? Vec3(Vec3::Zero()) : latest_.centre_of_mass);
  out.endSection(section);
}

namespace {

/// A bond count of the restored latest row: a whole number in [0, 2^53] (exact in a double).
std::uint64_t readBondCount(const StateReader& s, double value, const std::string& column) {
  if (!(value >= 0.0 && value <= 0x1p53 && value == std::floor(value))) {
    s.fail(std::to_string(value), "latest sample's " + column + " is not a bond count (a whole number >= 0)");
  }
  return static_cast<std::uint64_t>(value);
}

}  // namespace

void RegionSensor::loadState(StateReader& in) {
  SampledComponent::loadState(in);
  StateReader s = componentSection(in, "REGN", "latest");
  RegionReading r;
  r.time = readFinite(s, "time of the latest reading");
  r.count = s.read<std::uint64_t>();
  r.mass = readNonNegative(s, "mass of the latest reading");
  r.mean_velocity = s.read<Vec3>();
  r.centre_of_mass = s.read<Vec3>();
  s.requireEnd();
  if (!r.mean_velocity.allFinite() || !r.centre_of_mass.allFinite()) {
    s.fail("non-finite", "mean velocity or centre of mass of the latest reading");
  }
  if (r.count == 0) r.mean_velocity = r.centre_of_mass = emptyRegionMean();
  if (counts_bonds_) {
    // REGN has no bond counts (so checkpoints of scenes without bonds keep their bytes);
    // the latest row restored by SampledComponent holds them as they were sampled.
    const std::vector<double>& row = latestRow();
    r.bonds_intact = readBondCount(s, row[row.size() - 2], "bonds_intact");
    r.bonds_broken = readBondCount(s, row[row.size() - 1], "bonds_broken");
  }
  latest_ = r;
}

std::vector<std::string> RegionSensor::columns() const {
  std::vector<std::string> names{"time_s",      "count",   "mass_kg", "mean_vx_m_s", "mean_vy_m_s",
                                 "mean_vz_m_s", "com_x_m", "com_y_m", "com_z_m"};
  if (counts_bonds_) names.insert(names.end(), {"bonds_intact", "bonds_broken"});
  return names;
}

}  // namespace demlink::core
