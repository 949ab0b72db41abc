#pragma once
/// An infinite plane wall, one-sided: particles touch it from the side its unit
/// normal points to. It keeps a near list (particles within r + skin at the last
/// neighbour build) with one tangential history per entry, and accumulates the
/// force and torque the particles exert on it (about its point).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/particles/particle_arrays.hpp"

namespace demlink::core {

class StateWriter;
class StateReader;

struct PlaneSpec {
  std::string name;
  Vec3 point = Vec3::Zero();         ///< any point on the plane [m]
  Vec3 normal = Vec3::UnitZ();       ///< towards the particles' side (normalised on add)
  std::uint32_t material = 0;
  /// Does not deform: World::addPlane gives it the rigid twin of its material
  /// (Material::rigid), so the particle alone sets the contact stiffness.
  bool rigid = false;
};

/// What a range of slots of a plane's near list adds to the wall [N, N m about spec.point].
struct PlaneLoad {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
};

struct PlaneWall {
  PlaneSpec spec;
  std::vector<std::uint32_t> near_slots;
  std::vector<Vec3> near_history;
  Vec3 force = Vec3::Zero();   ///< on the wall by the particles [N]
  Vec3 torque = Vec3::Zero();  ///< about spec.point [N m]

  /// Rebuilds the near list, carrying histories over (see NeighbourList::build).
  void buildNearList(const ParticleArrays& particles, double skin, std::span<const std::uint32_t> newSlotOfOld);

  /// Checkpoint payload (one plane of section PLAN): name, near list, histories, wrench.
  void save(StateWriter& out) const;
  /// Reads what save() wrote into a plane of the same scene (same name); near-list
  /// slots must be below `slotCount` (rows of the last neighbour build). Throws
  /// InputError via in.fail(); the plane is unchanged then.
  void restore(StateReader& in, std::size_t slotCount);
};

}  // namespace demlink::core
