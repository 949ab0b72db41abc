#pragma once
/// A region sensor: number, mass, mean velocity and centre of mass of the particles
/// whose centre lies inside a box or sphere region, sampled at a fixed interval. The
/// region may be fixed, move with a constant velocity, or ride on a mesh body (e.g. the
/// fill of an excavator bucket).
///
/// Why centre membership: it is the coupling paper's definition (sec. 5.2), makes a
/// particle count once across adjacent regions, and costs one transform per particle.
/// Mean velocity is mass-weighted (total momentum / total mass), i.e. the velocity of
/// the contents' centre of mass; for equal masses it is the plain mean.
///
/// Parallel bonds (bonds/bond_set.hpp) are counted by their midpoint, the middle of the
/// two particles' centres now: a bond belongs to one region whichever of its particles
/// is inside, as a particle does, and a broken bond is counted where its particles are.
/// Bonds lost with a removed particle are no longer counted anywhere.
#include <cstdint>

#include "demlink/core/regions/region_shape.hpp"
#include "demlink/core/components/sampled_component.hpp"

namespace demlink::core {

/// What a region sensor measured at one time.
struct RegionReading {
  double time = 0.0;                 ///< [s]
  std::uint64_t count = 0;           ///< particles inside [-]
  double mass = 0.0;                 ///< [kg]
  Vec3 mean_velocity = Vec3::Zero();   ///< sum m v / sum m [m/s]; NaN when empty
  Vec3 centre_of_mass = Vec3::Zero();  ///< sum m x / sum m [m]; NaN when empty
  std::uint64_t bonds_intact = 0;    ///< intact parallel bonds whose midpoint is inside [-]
  std::uint64_t bonds_broken = 0;    ///< broken parallel bonds whose midpoint is inside [-]
};

class RegionSensor final : public SampledComponent {
 public:
  /// The placement is validated against fieldPrefix + ".region".
  RegionSensor(std::string name, VolumeShape shape, RegionPlacement placement, SampleSchedule schedule,
               std::string fieldPrefix);

  [[nodiscard]] std::string_view kind() const override { return "region_sensor"; }
  [[nodiscard]] StageSet stages() const override { return stageBit(Stage::kObserve); }
  void initialize(ComponentWorld& world) override;
  void observe(const ComponentWorld& world) override;
  /// time_s, count, mass_kg, mean_vx_m_s, mean_vy_m_s, mean_vz_m_s, com_x_m, com_y_m, com_z_m,
  /// and, in a world with bond rules (known from initialize() on), bonds_intact, bonds_broken.
  /// Why only then: the sensors of scenes without bonds keep their columns and checkpoints.
  [[nodiscard]] std::vector<std::string> columns() const override;
  /// Schedule, then a "REGN" section with the latest reading but its bond counts: those
  /// are the last two values of the schedule's latest row, and loadState takes them from
  /// there, so a restored latest() equals the uninterrupted run's.
  void saveState(StateWriter& out) const override;
  void loadState(StateReader& in) override;

  /// Measures the world's current state (does not record a sample).
  [[nodiscard]] RegionReading measure(const ComponentWorld& world) const;
  /// The last sample.
  [[nodiscard]] const RegionReading& latest() const { return latest_; }
  /// Moves or resizes the region from the world's current time on (checkpoints keep it
  /// through saveInputs).
  /// Throws InputError naming `fieldPrefix`.<field>; nothing changes then.
  void changeRegion(const ComponentWorld& world, const RegionChange& change, const std::string& fieldPrefix);
  [[nodiscard]] bool inputsChanged() const override { return inputs_changed_; }
  /// The region (shape and placement).
  void saveInputs(StateWriter& out) const override;
  void loadInputs(StateReader& in) override;
  [[nodiscard]] const VolumeShape& shape() const { return shape_; }
  [[nodiscard]] const RegionPlacement& placement() const { return placement_; }

 private:
  void sample(const ComponentWorld& world);

  VolumeShape shape_;
  RegionPlacement placement_;
  bool inputs_changed_ = false;
  bool counts_bonds_ = false;  ///< the world has bond rules: the samples carry the bond counts
  RegionReading latest_;
};

}  // namespace demlink::core
