#pragma once
/// ParallelBonds: cements touching spheres with parallel bonds (Potyondy and Cundall
/// 2004), the scene's `parallel_bonds` component (docs/reference/parallel_bonds.md).
/// The server checks every field when the scene compiles and names the bad one.
///
/// Why declared only: a rule makes its bonds once, at its creation time; the bonds are
/// then read through region sensors (RegionSensor::bondsIntact, bondsBroken).
#include <cstdint>
#include <string>

#include "demlink/client/component.hpp"

namespace demlink::client {

class ParallelBonds : public Component {
 public:
  explicit ParallelBonds(std::string name);
  /// kn and ks [Pa/m], > 0.
  ParallelBonds& setStiffnessPerArea(double normal, double shear);
  /// Tensile strength and cohesion [Pa], > 0.
  ParallelBonds& setStrength(double tensile, double shear);
  ParallelBonds& setGapTolerance(double metres);     ///< largest surface gap of a bonded pair [m], >= 0
  ParallelBonds& setRadiusMultiplier(double lambda);  ///< bond radius / smaller sphere radius [-], (0, 1]
  ParallelBonds& setCreateTime(double seconds);       ///< [s], >= 0 (default 0: at the first step)
  ParallelBonds& setFraction(double fraction, std::uint64_t seed = 0);  ///< of the candidate pairs [-], (0, 1]
  /// Both spheres of one of the named materials (call once per material; none: any).
  ParallelBonds& addMaterial(const std::string& material);
  /// Pairs with both centres inside (none: everywhere) [m].
  ParallelBonds& setBox(const Vec3& centre, const Vec3& size, const Quat& orientation = {});
  ParallelBonds& setSphere(const Vec3& centre, double radius);
  /// The region rides on this mesh body (its centre in the body's frame).
  ParallelBonds& attachTo(const std::string& meshComponent);
  [[nodiscard]] v1::ParallelBonds& message();
};

}  // namespace demlink::client
