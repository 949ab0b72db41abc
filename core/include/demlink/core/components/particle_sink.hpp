#pragma once
/// A particle sink: removes, every step, the particles whose centre lies inside a box or
/// sphere region (which may move or ride on a mesh body) and tallies their number and
/// mass, in total and per sample interval.
///
/// Why in the insert_remove stage (before the drift): removed particles take no part in this step's
/// contacts, and the world compacts its arrays once for the sink and the domain bounds.
/// The tally is what the world lost: the test MassBalance checks that the world's mass
/// drop equals the sink's removed mass.
#include "demlink/core/regions/region_shape.hpp"
#include "demlink/core/components/sampled_component.hpp"
#include "demlink/core/components/component_world.hpp"

namespace demlink::core {

class ParticleSink final : public SampledComponent {
 public:
  /// `fieldPrefix` names the declaration in errors (e.g. "components[4].particle_sink");
  /// the placement is validated against fieldPrefix + ".region".
  ParticleSink(std::string name, VolumeShape shape, RegionPlacement placement, SampleSchedule schedule,
               std::string fieldPrefix);

  [[nodiscard]] std::string_view kind() const override { return "particle_sink"; }
  [[nodiscard]] StageSet stages() const override { return stageBit(Stage::kInsertRemove) | stageBit(Stage::kObserve); }
  void initialize(ComponentWorld& world) override;
  void insertAndRemove(ComponentWorld& world) override;
  void observe(const ComponentWorld& world) override;
  /// time_s, removed_interval, removed_mass_interval_kg, removed_total, removed_mass_total_kg
  [[nodiscard]] std::vector<std::string> columns() const override;
  /// Schedule, then a "SINK" section: total, since-last-sample and last-interval tallies.
  void saveState(StateWriter& out) const override;
  void loadState(StateReader& in) override;

  /// Everything removed since the start [count, kg].
  [[nodiscard]] const RemovalTally& total() const { return total_; }
  /// Removed during the last complete sample interval.
  [[nodiscard]] const RemovalTally& lastInterval() const { return last_interval_; }
  /// Run-time control from the world's current time on (checkpoints keep it through
  /// saveInputs): an off sink removes nothing; changeRegion() as RegionSensor::changeRegion.
  void setEnabled(bool enabled) {
    enabled_ = enabled;
    inputs_changed_ = true;
  }
  [[nodiscard]] bool enabled() const { return enabled_; }
  void changeRegion(const ComponentWorld& world, const RegionChange& change, const std::string& fieldPrefix);
  [[nodiscard]] bool inputsChanged() const override { return inputs_changed_; }
  /// On/off and the region (shape and placement).
  void saveInputs(StateWriter& out) const override;
  void loadInputs(StateReader& in) override;
  [[nodiscard]] const VolumeShape& shape() const { return shape_; }
  [[nodiscard]] const RegionPlacement& placement() const { return placement_; }

 private:
  VolumeShape shape_;
  RegionPlacement placement_;
  RemovalTally total_;
  RemovalTally since_sample_;
  RemovalTally last_interval_;
  bool enabled_ = true;
  bool inputs_changed_ = false;
};

}  // namespace demlink::core
