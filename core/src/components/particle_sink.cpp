/// Particle sink (contract in particle_sink.hpp).
///
/// The region's pose is taken at the start of the step (world.time() in stage 2), the
/// particles' positions too; an attached region uses the mesh pose after this step's
/// prescribed motion (stage 1), i.e. it leads the particles by one step.
#include "demlink/core/components/particle_sink.hpp"

#include "demlink/core/components/component_state.hpp"

namespace demlink::core {

ParticleSink::ParticleSink(std::string name, VolumeShape shape, RegionPlacement placement, SampleSchedule schedule,
                           std::string fieldPrefix)
    : SampledComponent(std::move(name), schedule, std::move(fieldPrefix)),
      shape_(shape),
      placement_(std::move(placement)) {
  placement_.validate(this->fieldPrefix() + ".region");
}

void ParticleSink::initialize(ComponentWorld& world) {
  placement_.resolve(world.meshes().size(), fieldPrefix() + ".region");
  resolveSchedule(world);
  publish(world, {world.time(), 0.0, 0.0, 0.0, 0.0});
}

void ParticleSink::changeRegion(const ComponentWorld& world, const RegionChange& change, const std::string& fieldPrefix) {
  applyRegionChange(change, world.time(), shape_, placement_, fieldPrefix);
  inputs_changed_ = true;
}

void ParticleSink::saveInputs(StateWriter& out) const {
  const std::size_t section = out.beginSection("SNKI");
  out.write(static_cast<std::uint8_t>(enabled_));
  writeRegionInputs(out, shape_, placement_);
  out.endSection(section);
}

void ParticleSink::loadInputs(StateReader& in) {
  StateReader s = componentSection(in, "SNKI", "sink_inputs");
  const bool enabled = readFlag(s, "enabled flag");
  readRegionInputs(s, shape_, placement_);
  s.requireEnd();
  enabled_ = enabled;
  inputs_changed_ = true;
}

void ParticleSink::insertAndRemove(ComponentWorld& world) {
  if (!enabled_) return;
  const RegionPose pose = placement_.poseAt(world.meshes(), world.time());
  const std::vector<Vec3>& position = world.particles().position;
  RemovalTally removed;
  world.removeParticles([&](std::size_t i) { return shape_.contains(pose, position[i]); }, removed);
  total_.count += removed.count;
  total_.mass += removed.mass;
  since_sample_.count += removed.count;
  since_sample_.mass += removed.mass;
}

void ParticleSink::observe(const ComponentWorld& world) {
  if (!sampleDue(world)) return;
  last_interval_ = since_sample_;
  since_sample_ = {};
  publish(world, {world.time(), static_cast<double>(last_interval_.count), last_interval_.mass,
           static_cast<double>(total_.count), total_.mass});
}

void ParticleSink::saveState(StateWriter& out) const {
  SampledComponent::saveState(out);
  const std::size_t section = out.beginSection("SINK");
  writeRemovalTally(out, total_);
  writeRemovalTally(out, since_sample_);
  writeRemovalTally(out, last_interval_);
  out.endSection(section);
}

void ParticleSink::loadState(StateReader& in) {
  SampledComponent::loadState(in);
  StateReader s = componentSection(in, "SINK", "tallies");
  const RemovalTally total = readRemovalTally(s, "removed total");
  const RemovalTally since = readRemovalTally(s, "removed since the last sample");
  const RemovalTally last = readRemovalTally(s, "removed in the last interval");
  s.requireEnd();
  if (since.count > total.count || last.count > total.count) {
    s.fail(std::to_string(total.count), "removed total is smaller than an interval's count");
  }
  total_ = total;
  since_sample_ = since;
  last_interval_ = last;
}

std::vector<std::string> ParticleSink::columns() const {
  return {"time_s", "removed_interval", "removed_mass_interval_kg", "removed_total", "removed_mass_total_kg"};
}

}  // namespace demlink::core
