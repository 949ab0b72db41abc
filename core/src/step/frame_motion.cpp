/// Fictitious forces of a moving frame; equations and the splitting are explained
/// in frame_motion.hpp. Everything that does not depend on the particle (the
/// effective gravity g - a_f, the rotation coefficients) is computed once per call.
#include "demlink/core/step/frame_motion.hpp"

#include <cmath>

#include "demlink/core/base/input_bounds.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/step/integrator.hpp"
#include "demlink/core/parallel/parallel_loops.hpp"

namespace demlink::core {
namespace {

/// Rotation of vectors by a fixed angle about a fixed unit axis (Rodrigues):
///   v' = v cos(phi) + (k x v) sin(phi) + k (k . v) (1 - cos(phi)).
/// A zero axis is the identity.
struct AxisRotation {
  Vec3 axis = Vec3::Zero();
  double cosine = 1.0;
  double sine = 0.0;

  AxisRotation(const Vec3& omega, double anglePerRate) {
    const double rate = omega.norm();
    if (rate > 0.0) {
      axis = omega / rate;
      cosine = std::cos(rate * anglePerRate);
      sine = std::sin(rate * anglePerRate);
    }
  }
  [[nodiscard]] Vec3 apply(const Vec3& v) const {
    return v * cosine + axis.cross(v) * sine + axis * (axis.dot(v) * (1.0 - cosine));
  }
};

/// Per-call constants of a half kick of length h.
struct FrameKickTerms {
  Vec3 effective_gravity;  ///< g - a_f [m/s^2]
  Vec3 alpha;              ///< [rad/s^2]
  Vec3 omega;              ///< [rad/s]
  Vec3 origin;             ///< [m]
  AxisRotation coriolis;   ///< dv/dt = -2 Omega x v over h
  AxisRotation spin;       ///< domega_p/dt = -Omega x omega_p over h

  FrameKickTerms(const Vec3& gravity, const FrameMotion& f, double h)
      : effective_gravity(gravity - f.linear_acceleration),
        alpha(f.angular_acceleration),
        omega(f.angular_velocity),
        origin(f.origin),
        coriolis(f.angular_velocity, -2.0 * h),
        spin(f.angular_velocity, -h) {}

  /// Velocity-independent acceleration at position x [m/s^2].
  [[nodiscard]] Vec3 acceleration(const Vec3& force, double invMass, const Vec3& x) const {
    const Vec3 r = x - origin;
    return force * invMass + effective_gravity - alpha.cross(r) - omega.cross(omega.cross(r));
  }
};

/// Strang-split half kick of one particle (see frame_motion.hpp).
inline void kickOne(ParticleArrays& p, std::size_t i, const FrameKickTerms& t, double halfH) {
  const Vec3 b = t.acceleration(p.force[i], p.inv_mass[i], p.position[i]);
  p.velocity[i] = t.coriolis.apply(p.velocity[i] + b * halfH) + b * halfH;
  const Vec3 c = p.torque[i] * p.inv_inertia[i] - t.alpha;
  p.angular_velocity[i] = t.spin.apply(p.angular_velocity[i] + c * halfH) + c * halfH;
}

/// A frame that only translates: its fictitious force is a uniform shift of gravity.
bool translatesOnly(const FrameMotion& f) { return f.angular_velocity.isZero(0.0) && f.angular_acceleration.isZero(0.0); }

}  // namespace

bool FrameMotion::isInertial() const {
  return linear_acceleration.isZero(0.0) && angular_velocity.isZero(0.0) && angular_acceleration.isZero(0.0);
}

void FrameMotion::validate(const std::string& fieldPrefix) const {
  requireBoundedVector(fieldPrefix + ".linear_acceleration", linear_acceleration, kMaxAcceleration, "m/s^2");
  requireBoundedVector(fieldPrefix + ".angular_velocity", angular_velocity, kMaxAngularVelocity, "rad/s");
  requireBoundedVector(fieldPrefix + ".angular_acceleration", angular_acceleration, kMaxAngularAcceleration,
                       "rad/s^2");
  requireBoundedVector(fieldPrefix + ".origin", origin, kMaxCoordinate, "m");
}

void FrameMotion::save(StateWriter& out) const {
  out.write(linear_acceleration);
  out.write(angular_velocity);
  out.write(angular_acceleration);
  out.write(origin);
}

void FrameMotion::restore(StateReader& in) {
  FrameMotion staged;
  staged.linear_acceleration = in.read<Vec3>();
  staged.angular_velocity = in.read<Vec3>();
  staged.angular_acceleration = in.read<Vec3>();
  staged.origin = in.read<Vec3>();
  *this = staged;
}

void frameKick(ParticleArrays& p, const Vec3& gravity, const FrameMotion& frame, double h, ThreadPool* pool) {
  if (translatesOnly(frame)) return kick(p, gravity - frame.linear_acceleration, h, pool);
  const FrameKickTerms terms(gravity, frame, h);
  const double halfH = 0.5 * h;
  parallelChunks(pool, p.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) kickOne(p, i, terms, halfH);
  });
}

void frameKickAndDrift(ParticleArrays& p, const Vec3& gravity, const FrameMotion& frame, double h, double dt,
                       ThreadPool* pool) {
  if (translatesOnly(frame)) return kickAndDrift(p, gravity - frame.linear_acceleration, h, dt, pool);
  const FrameKickTerms terms(gravity, frame, h);
  const double halfH = 0.5 * h;
  parallelChunks(pool, p.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      kickOne(p, i, terms, halfH);
      p.position[i] += p.velocity[i] * dt;
    }
  });
}

void frameExplicitEulerStep(ParticleArrays& p, const Vec3& gravity, const FrameMotion& frame, double dt,
                            ThreadPool* pool) {
  if (translatesOnly(frame)) return explicitEulerStep(p, gravity - frame.linear_acceleration, dt, pool);
  // First order by design: the same explicit update as explicitEulerStep, with the
  // fictitious accelerations evaluated at the old state.
  const FrameKickTerms terms(gravity, frame, dt);
  parallelChunks(pool, p.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const Vec3 v = p.velocity[i];
      const Vec3 a = terms.acceleration(p.force[i], p.inv_mass[i], p.position[i]) - 2.0 * terms.omega.cross(v);
      const Vec3 w = p.angular_velocity[i];
      const Vec3 spinRate = p.torque[i] * p.inv_inertia[i] - terms.alpha - terms.omega.cross(w);
      p.position[i] += v * dt;
      p.velocity[i] = v + a * dt;
      p.angular_velocity[i] = w + spinRate * dt;
    }
  });
}

}  // namespace demlink::core
