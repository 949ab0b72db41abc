#pragma once
/// ParticleSource: inserts particles into a region at a steady rate during a run
/// (the coupling paper's "ParticleSource", the solver paper's particle generator).
///
/// Why it works this way:
///   - Drift-free rate: the number (or mass) requested by the end of a step is
///     rate x active time, computed afresh each step, not accumulated, so a long
///     run neither drifts nor loses fractional particles; the fraction carries over.
///     kg/s rates are met in mass directly: the next particle (already drawn) goes in
///     once the requested mass covers it, so inserted mass is within one particle of
///     the request regardless of how sizes scatter.
///   - No overlaps at insertion: a candidate position is kept only if the sphere is
///     clear of every particle (local spatial hash over the particles near the region,
///     rebuilt only in steps that insert), every plane and every mesh triangle.
///   - No silent under-delivery: a particle that finds no free place within
///     max_attempts draws is counted as shortfall (count and mass), warned about
///     (first time, then each time the shortfall doubles) and reported.
///   - Clumps: with SourceShape::ClumpTemplate each insertion is one rigid clump
///     (World::addClump) with a seeded uniform random orientation; placement tests
///     the template's bounding sphere about its COM, so a clump never overlaps
///     anything whatever its orientation; rates and the report count clumps and
///     clump masses.
/// The source runs in the insert_remove stage (after mesh motion), so an attached region follows the
/// mesh's pose of the current step.
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string_view>
#include <utility>
#include <string>
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/base/random.hpp"
#include "demlink/core/components/size_distribution.hpp"
#include "demlink/core/components/world_component.hpp"

namespace demlink::core {

class ComponentWorld;

/// Where new particles appear, in the region's own frame (the world frame for a
/// fixed region, the mesh body's frame when attached).
struct SourceRegion {
  enum class Kind : std::uint8_t { Box, Disc };
  Kind kind = Kind::Box;
  Vec3 centre = Vec3::Zero();            ///< [m]
  Quat orientation = Quat::Identity();   ///< region axes relative to its frame [-]
  Vec3 half_extents = Vec3::Zero();      ///< Box: half sizes along the region's axes [m], > 0
  double radius = 0.0;                   ///< Disc: radius [m], > 0; the disc's normal is the region's z axis
  double thickness = 0.0;                ///< Disc: extent along its normal [m], >= 0; 0 = thin (centres on the disc)

  /// Throws InputError naming `fieldPrefix + ".<field>"`; `largestRadius` must fit.
  void validate(const std::string& fieldPrefix, double largestRadius) const;
  /// Radius of a sphere about `centre` that contains the region [m].
  [[nodiscard]] double boundingRadius() const;
  /// A uniformly distributed centre (region frame) for a sphere of radius r that fits.
  [[nodiscard]] Vec3 samplePoint(Random& rng, double r) const;
};

/// What a source inserts: spheres drawn from `sizes`, or clumps of one template
/// (`sizes` is then unused).
enum class SourceShape : std::uint8_t { Sphere, ClumpTemplate };

/// Throws InputError naming `field` unless `rate` is finite, >= 0 and at most
/// kMaxSourceParticleRate (`perParticle`) or kMaxSourceMassRate: one rule for a declared
/// rate and one sent at run time.
void requireSourceRate(const std::string& field, double rate, bool perParticle);

struct ParticleSourceSpec {
  SourceRegion region;
  /// Name of the mesh body the region is attached to (empty: fixed in the world frame).
  std::string attached_mesh;
  /// Attached only: add the body's velocity at the insertion point to `velocity`.
  bool add_body_velocity = true;
  std::optional<double> rate_particles_per_s;  ///< [1/s], >= 0; exactly one of the two rates
  std::optional<double> rate_kg_per_s;         ///< [kg/s], >= 0
  double start_time = 0.0;                               ///< [s], >= 0
  double stop_time = std::numeric_limits<double>::infinity();  ///< [s], > start_time
  std::uint32_t material = 0;
  SizeDistribution sizes;  ///< Sphere only
  Vec3 velocity = Vec3::Zero();          ///< initial velocity, world frame [m/s]
  Vec3 angular_velocity = Vec3::Zero();  ///< initial angular velocity, world frame [rad/s]
  std::uint64_t seed = 0;
  std::uint32_t max_attempts = 50;  ///< placement draws per particle, >= 1
  SourceShape shape = SourceShape::Sphere;
  std::uint32_t clump_template = 0;  ///< ClumpTemplate only: index from World::addClumpTemplate

  /// Throws InputError naming `fieldPrefix + ".<field>"` (material count checked by addParticleSource).
  /// For clumps the region is checked against `clumpBoundingRadius` [m] (the
  /// template's, known once the world is at hand; 0 skips the fit check).
  void validate(const std::string& fieldPrefix, double clumpBoundingRadius = 0.0) const;
};

/// Cumulative bookkeeping of a source.
/// For a clump source, counts are clumps and masses clump masses.
struct SourceReport {
  std::uint64_t inserted_count = 0;
  double inserted_mass = 0.0;      ///< [kg]
  std::uint64_t shortfall_count = 0;  ///< particles requested but not placed
  double shortfall_mass = 0.0;     ///< [kg]
  double requested_count = 0.0;    ///< rate x active time (estimate via the mean mass for kg/s) [-]
  double requested_mass = 0.0;     ///< [kg] (estimate via the mean mass for particles/s)
};

class ParticleSource final : public WorldComponent {
 public:
  /// Prefer addParticleSource(), which also declares the future particle sizes.
  ParticleSource(std::string name, ParticleSourceSpec spec, std::string fieldPrefix);

  [[nodiscard]] std::string_view kind() const override { return "particle_source"; }
  [[nodiscard]] StageSet stages() const override { return stageBit(Stage::kInsertRemove); }
  void initialize(ComponentWorld& world) override;
  void insertAndRemove(ComponentWorld& world) override;
  /// Insertion speed plus the spin at the rim (and the attached body's speed when added).
  [[nodiscard]] std::optional<double> largestSpeed(const ComponentWorld& world) const override;
  /// A "SRCE" section: generator state, the drawn particle waiting for its mass (kg/s),
  /// the consumed mass, the report and the shortfall log mark.
  void saveState(StateWriter& out) const override;
  void loadState(StateReader& in) override;

  /// Run-time control from the world's current time on (a co-simulation client's
  /// ParticleSourceInput; checkpoints keep it through saveInputs). The request accumulated so far is kept and
  /// the new state applies to the active time that follows: an off source requests
  /// nothing. The rate is in the declared unit (particles/s or kg/s), >= 0; throws
  /// InputError naming `field` otherwise.
  void setEnabled(const ComponentWorld& world, bool enabled);
  void setRate(const ComponentWorld& world, double rate, const std::string& field);
  [[nodiscard]] bool enabled() const { return enabled_; }
  [[nodiscard]] bool inputsChanged() const override { return inputs_changed_; }
  /// On/off, the rate and the request accumulated before the current rate segment.
  void saveInputs(StateWriter& out) const override;
  void loadInputs(StateReader& in) override;
  /// The current rate in the declared unit [1/s or kg/s].
  [[nodiscard]] double rate() const;
  [[nodiscard]] const SourceReport& report() const { return report_; }
  /// Adds to the report what another engine inserted for this source (the LIGGGHTS
  /// backend's insertion fix: that engine places the particles, so insertAndRemove never
  /// runs there and the client's outputs come from here).
  void countInsertedElsewhere(std::uint64_t count, double mass);
  [[nodiscard]] const ParticleSourceSpec& spec() const { return spec_; }
  /// One line for logs: inserted count and mass, shortfall, requested.
  [[nodiscard]] std::string summaryLine() const;
  /// World pose of the region frame at the current step: x_world = position + R x_region.
  [[nodiscard]] std::pair<Vec3, Quat> regionPose(const ComponentWorld& world) const;

 private:
  struct Drawn {
    double radius = 0.0;  ///< sphere radius, or the clump's bounding radius [m]
    double mass = 0.0;    ///< [kg]
  };
  class Placement;

  Drawn draw();
  /// Largest radius a new shape occupies (sphere radius or clump bounding radius) [m].
  [[nodiscard]] double maxNewRadius() const;
  bool place(ComponentWorld& world, Placement& placement, const Drawn& shape);
  void insertSphere(ComponentWorld& world, const Vec3& position, const Vec3& velocity, double radius);
  /// Adds one clump of the template, COM at `position`, random orientation.
  void insertClump(ComponentWorld& world, const Vec3& position, const Vec3& velocity);
  void noteShortfall(const Drawn& shape, double time);
  /// `count` particles owed beyond kMaxSourcePlacementsPerStep in one step, not tried.
  void noteBulkShortfall(double count, double time);
  /// The request (count or kg) accumulated up to time `t` [s] at the current rate.
  [[nodiscard]] double requestedUntil(double t) const;
  /// Ends the current rate segment at time `t` [s] (before a change of rate or state).
  void closeSegment(double t);

  ParticleSourceSpec spec_;
  std::string field_prefix_;
  Random rng_;
  double density_ = 0.0;    ///< [kg/m^3]
  double mean_mass_ = 0.0;  ///< [kg]
  double clump_radius_ = 0.0;  ///< clumps: template bounding radius about the COM [m]
  double clump_mass_ = 0.0;    ///< clumps: mass of one clump [kg]
  std::optional<std::size_t> mesh_index_;
  std::optional<Drawn> next_;  ///< kg/s only: drawn, waiting for the requested mass to cover it
  double consumed_mass_ = 0.0;  ///< kg/s only: drawn mass inserted or counted as shortfall [kg]
  SourceReport report_;
  std::uint64_t shortfall_logged_ = 0;
  bool enabled_ = true;
  bool inputs_changed_ = false;
  double requested_before_ = 0.0;  ///< request (count or kg) up to segment_start_
  double segment_start_ = 0.0;     ///< [s] since when the current rate and state hold
};

/// Validates `spec`, declares its smallest radius (a clump's smallest member radius) as
/// a future particle size (the time step check then covers inserted particles) and
/// adds the source to the world. Clump templates must be registered before.
/// Call before World::initialize(). Throws InputError naming fieldPrefix + ".<field>".
ParticleSource& addParticleSource(ComponentWorld& world, const std::string& name, ParticleSourceSpec spec,
                                  const std::string& fieldPrefix);

}  // namespace demlink::core
