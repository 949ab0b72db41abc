#pragma once
/// A flow sensor: counts the particles (and their mass) whose centre crosses a flat
/// rectangle or disc, in each direction (positive = along the surface normal), per
/// sample interval and in total. The surface may be fixed, move with a constant
/// velocity, or ride on a mesh body.
///
/// Method: every step, each particle's centre is expressed in the surface's frame
/// (normal = local z). A crossing is a change of side (z > 0 against z <= 0) between
/// the particle's previous observation and this one; it counts only when the point
/// where the segment between the two positions meets z = 0 lies on the surface. Each
/// crossing is signed, so a particle oscillating across the surface adds to both
/// directional counts every time but its net contribution stays 0 or +-1.
///
/// Why only particles near the surface are remembered: previous positions are kept,
/// keyed by stable particle id (slots are permuted by the world), only for particles
/// within a band |z| <= h of the surface plane and within h of its outline, so memory
/// and hash-map work scale with the particles near the surface, not with N (the per-step
/// cost for the rest is one dot product). The band h = max(r_max / 2, 4 (v_max + v_s) dt
/// + |g| dt^2) (v_max the fastest particle, v_s the surface's speed bound) exceeds any
/// step's displacement, so no crossing starts outside it. A particle first seen inside
/// the band (just inserted, just arrived) has no previous position and cannot count,
/// and a removed particle's entry is dropped at the next step: neither produces a
/// false crossing.
#include <cstdint>
#include <unordered_map>

#include "demlink/core/regions/region_shape.hpp"
#include "demlink/core/components/sampled_component.hpp"

namespace demlink::core {

/// Crossings counted by a flow sensor.
struct FlowTally {
  std::uint64_t positive_count = 0;  ///< crossings along the normal [-]
  std::uint64_t negative_count = 0;  ///< crossings against the normal [-]
  double positive_mass = 0.0;        ///< [kg]
  double negative_mass = 0.0;        ///< [kg]

  /// positive - negative [-].
  [[nodiscard]] std::int64_t netCount() const {
    return static_cast<std::int64_t>(positive_count) - static_cast<std::int64_t>(negative_count);
  }
  /// positive - negative [kg].
  [[nodiscard]] double netMass() const { return positive_mass - negative_mass; }
};

class FlowSensor final : public SampledComponent {
 public:
  /// The placement's orientation maps local z to the surface normal (see
  /// surfaceOrientation()); it is validated against fieldPrefix + ".surface".
  FlowSensor(std::string name, SurfaceShape shape, RegionPlacement placement, SampleSchedule schedule,
             std::string fieldPrefix);

  [[nodiscard]] std::string_view kind() const override { return "flow_sensor"; }
  [[nodiscard]] StageSet stages() const override { return stageBit(Stage::kObserve); }
  void initialize(ComponentWorld& world) override;
  void observe(const ComponentWorld& world) override;
  /// time_s, then for the interval and the total: positive, negative and net count, and
  /// positive, negative and net mass [kg].
  [[nodiscard]] std::vector<std::string> columns() const override;
  /// Schedule, then a "FLOW" section: band width, the three tallies and the remembered
  /// (id, local position) pairs in increasing id order (so the bytes do not depend on
  /// the hash map's iteration order).
  void saveState(StateWriter& out) const override;
  void loadState(StateReader& in) override;

  /// Everything counted since the start.
  [[nodiscard]] const FlowTally& total() const { return total_; }
  /// Counted during the last complete sample interval.
  [[nodiscard]] const FlowTally& lastInterval() const { return last_interval_; }
  /// Particles whose previous position is currently remembered [-].
  [[nodiscard]] std::size_t trackedCount() const { return previous_.size(); }
  /// Current half-width of the remembered band [m].
  [[nodiscard]] double band() const { return band_; }
  [[nodiscard]] const SurfaceShape& shape() const { return shape_; }
  [[nodiscard]] const RegionPlacement& placement() const { return placement_; }
  /// Steps between two observations [-], >= 1: 1 in our engine (every step); an engine
  /// that hands the world over only every `steps` steps (the LIGGGHTS backend) sets it so
  /// the remembered band covers the displacement of that many steps. Crossings are then
  /// judged on the straight segment between two observations.
  void setObservationSpacing(std::uint64_t steps) { observation_spacing_ = steps > 0 ? steps : 1; }

 private:
  /// Scans the particles, counts crossings against previous_ (when `count`), refills the
  /// remembered band and updates its width.
  void scan(const ComponentWorld& world, bool count);
  void countCrossing(const Vec3& before, const Vec3& after, double mass);

  SurfaceShape shape_;
  RegionPlacement placement_;
  double band_ = 0.0;  ///< [m]
  std::unordered_map<std::uint64_t, Vec3> previous_;  ///< id -> local position at the last step
  std::unordered_map<std::uint64_t, Vec3> current_;   ///< scratch, swapped with previous_
  FlowTally total_;
  FlowTally since_sample_;
  FlowTally last_interval_;
  std::uint64_t observation_spacing_ = 1;  ///< steps between observations [-]
};

}  // namespace demlink::core
