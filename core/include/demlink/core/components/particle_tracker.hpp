#pragma once
/// A tracker: records chosen particles (by stable id) and mesh bodies (by index) at a
/// fixed sample interval. Per particle: position, velocity, angular velocity and contact
/// force; per mesh body: pose, velocity and the wrench the particles exert on it.
///
/// Why by id: slots are permuted by removals and cell sorts, ids never change. A tracked
/// particle that is not (yet) in the world, or that was removed (by a sink or the domain
/// bounds), is reported with a status and NaN values, never an error: the caller cannot
/// know in advance when a source inserts or a sink removes it.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "demlink/core/components/sampled_component.hpp"
#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

/// State of a tracked particle at a sample.
struct TrackedParticle {
  enum class Status : int { NotYetPresent = 0, Present = 1, Removed = -1 };
  std::uint64_t id = 0;
  Status status = Status::NotYetPresent;
  Vec3 position = Vec3::Zero();          ///< [m]
  Vec3 velocity = Vec3::Zero();          ///< [m/s]
  Vec3 angular_velocity = Vec3::Zero();  ///< [rad/s]
  Vec3 force = Vec3::Zero();             ///< contact force, gravity excluded [N]
};

/// State of a tracked mesh body at a sample.
struct TrackedMesh {
  std::size_t index = 0;
  Vec3 position = Vec3::Zero();           ///< reference point [m]
  Quat orientation = Quat::Identity();    ///< body -> world [-]
  Vec3 linear_velocity = Vec3::Zero();    ///< [m/s]
  Vec3 angular_velocity = Vec3::Zero();   ///< [rad/s]
  Vec3 force = Vec3::Zero();              ///< on the body by the particles [N]
  Vec3 torque = Vec3::Zero();             ///< about the reference point [N m]
};

class ParticleTracker final : public SampledComponent {
 public:
  /// Throws InputError naming fieldPrefix + ".particle_ids[k]" for id 0 or a repeated id,
  /// fieldPrefix + ".mesh_bodies[k]" for a repeated index, and fieldPrefix +
  /// ".particle_ids" when nothing is tracked. Mesh indices are checked by initialize().
  ParticleTracker(std::string name, std::vector<std::uint64_t> particleIds, std::vector<std::size_t> meshIndices,
                  SampleSchedule schedule, std::string fieldPrefix);

  [[nodiscard]] std::string_view kind() const override { return "tracker"; }
  [[nodiscard]] StageSet stages() const override { return stageBit(Stage::kObserve); }
  void initialize(ComponentWorld& world) override;
  void observe(const ComponentWorld& world) override;
  /// time_s; per particle p<id>_status (1 present, 0 not yet present, -1 removed),
  /// p<id>_{x,y,z}_m, _{vx,vy,vz}_m_s, _{wx,wy,wz}_rad_s, _{fx,fy,fz}_N; per mesh body
  /// <name>_{x,y,z}_m, _{qw,qx,qy,qz}, _{vx,vy,vz}_m_s, _{wx,wy,wz}_rad_s, _{fx,fy,fz}_N,
  /// _{tx,ty,tz}_N_m.
  [[nodiscard]] std::vector<std::string> columns() const override;
  /// Schedule, then a "TRAK" section: per tracked particle its id (checked against the
  /// scene's), status (which decides "removed" against "not yet present") and values;
  /// per tracked mesh its index and values.
  void saveState(StateWriter& out) const override;
  void loadState(StateReader& in) override;

  /// The last sample, in the order the ids / indices were given.
  [[nodiscard]] const std::vector<TrackedParticle>& particles() const { return particles_; }
  [[nodiscard]] const std::vector<TrackedMesh>& meshes() const { return meshes_; }

 private:
  void sample(const ComponentWorld& world);

  std::vector<TrackedParticle> particles_;
  std::vector<TrackedMesh> meshes_;
  std::vector<std::string> mesh_labels_;
  std::unordered_map<std::uint64_t, std::size_t> column_of_id_;
};

}  // namespace demlink::core
