#pragma once
/// Particle state as structure-of-arrays. Hot columns (position, velocity,
/// angular velocity, force, torque: 5 x 24 bytes) are what the force and
/// integration stages stream through; per-particle constants (radius, inverse
/// mass and inertia, material: 28 bytes) sit in their own columns; the stable id
/// is cold. Slots are dense [0, size()); they are reordered only by permute(),
/// which the world calls when it compacts removed particles or sorts by cell.
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

class StateWriter;
class StateReader;

/// Marks a removed slot in a slot mapping (newSlotOfOld).
inline constexpr std::uint32_t kRemovedSlot = std::numeric_limits<std::uint32_t>::max();

/// Everything needed to create one sphere.
struct ParticleSpec {
  Vec3 position = Vec3::Zero();          ///< [m]
  Vec3 velocity = Vec3::Zero();          ///< [m/s]
  Vec3 angular_velocity = Vec3::Zero();  ///< [rad/s]
  double radius = 0.0;                   ///< [m]
  std::uint32_t material = 0;            ///< index into the world's materials
};

struct ParticleArrays {
  std::vector<Vec3> position;          ///< [m]
  std::vector<Vec3> velocity;          ///< [m/s]
  std::vector<Vec3> angular_velocity;  ///< [rad/s]
  std::vector<Vec3> force;             ///< contact force of the last evaluation [N] (gravity excluded)
  std::vector<Vec3> torque;            ///< contact torque about the centre [N m]
  std::vector<double> radius;          ///< [m]
  std::vector<double> mass;            ///< [kg]
  std::vector<double> inv_mass;        ///< [1/kg]
  std::vector<double> inv_inertia;     ///< 1 / (2/5 m R^2) [1/(kg m^2)]
  std::vector<std::uint32_t> material;
  std::vector<std::uint64_t> id;       ///< stable, never reused
  /// Id of the clump this sphere belongs to (ClumpBody::id), 0 for a free sphere.
  /// A clump member's mass is its share of the clump mass (clump mass / member
  /// count, so sums over slots give the right total), while inv_mass is 1 / clump
  /// mass (contacts see the body's mass) and inv_inertia 1 / the body's smallest
  /// principal moment (docs/clumps.md).
  std::vector<std::uint64_t> clump_id;

  [[nodiscard]] std::size_t size() const { return position.size(); }

  /// Translational plus rotational kinetic energy of the free sphere in `slot` [J].
  [[nodiscard]] double sphereKineticEnergy(std::size_t slot) const {
    return 0.5 * mass[slot] * velocity[slot].squaredNorm() + 0.5 / inv_inertia[slot] * angular_velocity[slot].squaredNorm();
  }

  /// Appends a sphere with the given density [kg/m^3] and id.
  void append(const ParticleSpec& spec, double density, std::uint64_t stableId);

  /// Reorders (and possibly shrinks) every column: new slot k takes old slot
  /// oldSlotOfNew[k].
  void permute(std::span<const std::uint32_t> oldSlotOfNew);

  void reserve(std::size_t n);

  /// Checkpoint payload (section PART): row count, column count, then one `COL `
  /// sub-section per column (name, element size, values), in forEachColumn order.
  void save(StateWriter& out) const;
  /// Replaces every column with what save() wrote. Every column must be present
  /// with its element size and the common row count, and none unknown; throws
  /// InputError via in.fail() otherwise. Material indices are not checked here
  /// (the caller knows how many materials there are).
  void restore(StateReader& in);

  /// Calls visit(name, column) for every column, in a fixed order. permute(),
  /// reserve() and the checkpoint go through it, so a column added here is
  /// reordered, reserved and saved without further edits (append() still lists
  /// the columns one by one).
  template <class Visitor>
  void forEachColumn(Visitor&& visit) {
    visitColumns(*this, visit);
  }
  template <class Visitor>
  void forEachColumn(Visitor&& visit) const {
    visitColumns(*this, visit);
  }

 private:
  template <class Self, class Visitor>
  static void visitColumns(Self& self, Visitor& visit) {
    visit("position", self.position);
    visit("velocity", self.velocity);
    visit("angular_velocity", self.angular_velocity);
    visit("force", self.force);
    visit("torque", self.torque);
    visit("radius", self.radius);
    visit("mass", self.mass);
    visit("inv_mass", self.inv_mass);
    visit("inv_inertia", self.inv_inertia);
    visit("material", self.material);
    visit("id", self.id);
    visit("clump_id", self.clump_id);
  }
};

}  // namespace demlink::core
