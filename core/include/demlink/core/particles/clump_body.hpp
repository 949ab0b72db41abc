#pragma once
/// The rigid body of one clump and its time integration.
///
/// Why the member spheres stay ordinary particles: every contact kernel (pairs,
/// planes, meshes) keeps working on spheres unchanged. A clump only adds a pass
/// that sums its members' contact forces onto the body, integrates the body, and
/// writes the members' positions and velocities back from the body pose.
///
/// Rotation keeps the angular momentum L in the world frame: a torque kick is
/// L += T h (exact for the kick), and a drift rotates the orientation q with
/// L fixed, i.e. the torque-free motion, dq/dt = 1/2 (0, w) q with
/// w = R(q) I^-1 R(q)^T L (I the principal moments), integrated with classical RK4
/// in substeps of at most kMaxSubstepAngle rotation each and then renormalised.
/// L is therefore conserved exactly by a torque-free drift; the rotational energy
/// has the RK4 error, O((|w| dt)^5) per step (docs/clumps.md).
#include <cstdint>
#include <vector>

#include "demlink/core/particles/clump_template.hpp"
#include "demlink/core/base/math_types.hpp"
#include "demlink/core/particles/particle_arrays.hpp"

namespace demlink::core {

class StateWriter;
class StateReader;

/// Largest rotation angle of one RK4 substep of the orientation drift [rad].
inline constexpr double kMaxSubstepAngle = 0.05;
/// Most RK4 substeps of one drift (reached only at |w| dt > 50 rad: a blown-up state).
inline constexpr int kMaxSubsteps = 1000;

/// Everything needed to create one clump (World::addClump).
struct ClumpSpec {
  std::uint32_t template_index = 0;       ///< index returned by World::addClumpTemplate
  std::uint32_t material = 0;             ///< material index (density, contact properties of every member)
  Vec3 position = Vec3::Zero();           ///< where the clump's centre of mass goes [m]
  Quat orientation = Quat::Identity();    ///< rotation of the template's own frame into the world
  Vec3 velocity = Vec3::Zero();           ///< of the centre of mass [m/s]
  Vec3 angular_velocity = Vec3::Zero();   ///< world frame [rad/s]
};

struct ClumpBody {
  std::uint64_t id = 0;                   ///< stable clump id (>= 1, never reused); members carry it
  std::uint32_t template_index = 0;
  double mass = 0.0;                      ///< [kg]
  Vec3 inertia = Vec3::Zero();            ///< principal moments (body frame) [kg m^2]
  Vec3 position = Vec3::Zero();           ///< centre of mass [m]
  Vec3 velocity = Vec3::Zero();           ///< [m/s]
  Quat orientation = Quat::Identity();    ///< body (principal) frame -> world, unit
  Vec3 angular_momentum = Vec3::Zero();   ///< about the COM, world frame [kg m^2/s]
  Vec3 force = Vec3::Zero();              ///< sum of member contact forces [N] (gravity excluded)
  Vec3 torque = Vec3::Zero();             ///< about the COM, world frame [N m]
  std::vector<std::uint32_t> member_slots;  ///< slot of each template sphere, in template order

  /// w = R I^-1 R^T L [rad/s], world frame.
  [[nodiscard]] Vec3 angularVelocity() const { return angularVelocityAt(orientation); }
  [[nodiscard]] Vec3 angularVelocityAt(const Quat& q) const;
  /// Translational + rotational kinetic energy [J].
  [[nodiscard]] double kineticEnergy() const;

  /// Checkpoint payload of one body: every field above, in declaration order.
  void save(StateWriter& out) const;
  /// Reads what save() wrote; the template index must name one of `templates`, the
  /// member count match that template and the member slots be below `slotCount`.
  /// Throws InputError via in.fail(); the body is unchanged then.
  void restore(StateReader& in, const std::vector<ClumpTemplate>& templates, std::size_t slotCount);
};

/// Checkpoint payload of the live clumps (in section CLMP): count, then each body.
void saveClumps(StateWriter& out, const std::vector<ClumpBody>& clumps);
/// Reads what saveClumps wrote (see ClumpBody::restore for the checks).
[[nodiscard]] std::vector<ClumpBody> restoreClumps(StateReader& in, const std::vector<ClumpTemplate>& templates,
                                                   std::size_t slotCount);

/// v += (F/m + g) h; L += T h.
void kickClump(ClumpBody& body, const Vec3& gravity, double h);
/// x += v dt; torque-free rotation of q over dt (RK4 substeps, renormalised).
void driftClump(ClumpBody& body, double dt);
/// Sums the members' contact forces and torques (r x f + t) onto the body.
void gatherClumpForces(ClumpBody& body, const ParticleArrays& particles);
/// Writes member velocities (v + w x r) and angular velocities (w); also the
/// positions (x + R b) when `positions` is true.
void placeClumpMembers(const ClumpBody& body, const ClumpTemplate& shape, ParticleArrays& particles, bool positions);

}  // namespace demlink::core
