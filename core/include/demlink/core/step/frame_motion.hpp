#pragma once
/// The moving frame: the reference frame particles are integrated in. It may
/// accelerate and rotate with everything at rest in it (planes, meshes), as the
/// coupling paper's accelerated, rotating simulation domain does (a truck bed that
/// brakes and turns); docs/frame_and_facets.md describes it for users.
///
/// Equations (all vectors in frame coordinates; r = x - origin, v and omega_p the
/// particle's velocity and spin RELATIVE to the frame):
///   dv/dt       = F/m + g - a_f - alpha x r - Omega x (Omega x r) - 2 Omega x v
///   domega_p/dt = T/I - alpha - Omega x omega_p
/// with a_f the acceleration of the frame's origin, Omega its angular velocity and
/// alpha = dOmega/dt. The last term is the exact Euler equation of a sphere
/// (isotropic inertia) seen from the rotating frame: the absolute spin
/// omega_p + Omega obeys I d/dt|inertial = T. Gravity g is given in frame
/// coordinates and stays constant there (World::setGravity changes it).
///
/// Integration (why): the Coriolis term -2 Omega x v and the spin transport
/// -Omega x omega_p depend on the velocity being kicked, and both are pure
/// rotations (they do no work). Each half kick of length h is therefore split
/// symmetrically (Strang): add half the velocity-independent acceleration b(x),
/// rotate exactly (Rodrigues) by -2|Omega|h about Omega (spin: -|Omega|h), add the
/// other half. The half kick is time-symmetric and exact for the rotation, so the
/// kick-drift-kick step stays second order and speeds are not changed by the
/// Coriolis part at all. See docs/frame_and_facets.md for measured accuracy.
///
/// Cost: the world calls these routines only when the frame is not inertial; an
/// inertial frame runs the plain integrator (one branch per step, outside the loop).
/// A frame that only translates (Omega = alpha = 0) is exactly a gravity shift: the
/// routines then run the plain kick with g - a_f (bit-identical, no extra work).
#include <string>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/particles/particle_arrays.hpp"
#include "demlink/core/parallel/thread_pool.hpp"

namespace demlink::core {

class StateWriter;
class StateReader;

/// Motion of the frame relative to an inertial frame, expressed in frame coordinates.
/// linear_acceleration and angular_acceleration are constant until changed by
/// World::setFrameMotion (e.g. once per co-simulation interval); angular_velocity
/// is the value when set, and the world's running copy (WorldState::frame, not the
/// settings) advances it by angular_acceleration * dt every step (exact for a
/// constant alpha; each half kick uses the Omega of its time).
struct FrameMotion {
  Vec3 linear_acceleration = Vec3::Zero();   ///< acceleration of `origin` [m/s^2]
  Vec3 angular_velocity = Vec3::Zero();      ///< Omega [rad/s]
  Vec3 angular_acceleration = Vec3::Zero();  ///< alpha = dOmega/dt [rad/s^2]
  Vec3 origin = Vec3::Zero();                ///< point of the frame the rotation is about [m]

  /// True when all three motion vectors are exactly zero (no fictitious force).
  [[nodiscard]] bool isInertial() const;
  /// Throws InputError naming `fieldPrefix + ".<field>[k]"` for a non-finite component.
  void validate(const std::string& fieldPrefix) const;

  /// Checkpoint payload (in the checkpoint section FRAM): the four vectors in declaration order
  /// (angular_velocity as advanced so far).
  void save(StateWriter& out) const;
  /// Replaces the motion with what save() wrote (unchanged if the data ends early).
  void restore(StateReader& in);
};

/// Half kick in the frame: v and omega_p advance by h under contact forces, gravity
/// and the fictitious terms (positions unchanged).
void frameKick(ParticleArrays& p, const Vec3& gravity, const FrameMotion& frame, double h,
               ThreadPool* pool = nullptr);
/// frameKick(h) then x += v dt, in one pass.
void frameKickAndDrift(ParticleArrays& p, const Vec3& gravity, const FrameMotion& frame, double h, double dt,
                       ThreadPool* pool = nullptr);
/// Explicit Euler in the frame: accelerations (fictitious ones included) from the
/// OLD position and velocity; x += v_old dt; v += a_old dt.
void frameExplicitEulerStep(ParticleArrays& p, const Vec3& gravity, const FrameMotion& frame, double dt,
                            ThreadPool* pool = nullptr);

}  // namespace demlink::core
