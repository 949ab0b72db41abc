#pragma once
/// Contact force laws, as compile-time policy types. One kernel serves
/// particle-particle, particle-plane and particle-mesh contacts, so the force law
/// exists exactly once.
///
/// Conventions for a contact between body A and body B:
///   n       unit normal from A towards B; the normal force on B is +F_n n.
///   delta   overlap > 0.
///   v_rel   velocity of B's contact point relative to A's.
///   xi      tangential spring (history): accumulated tangential displacement of
///           B relative to A, kept in the current tangent plane.
/// The returned vector is the force ON B; A receives its negative.
///
/// Hertz-Mindlin (solver paper eqs. 5-8, corrected):
///   S_n = 2 E* sqrt(R* delta),   F_ne = 4/3 E* sqrt(R*) delta^(3/2) = 2/3 S_n delta
///   S_t = 8 G* sqrt(R* delta)    (the paper writes sqrt(R* delta_t); it is the normal overlap)
///   F_nd = gamma_n * (approach speed),  gamma_n = 2 sqrt(5/6) |beta| sqrt(S_n m*)
///          (the paper omits the square root on S_n m*)
///   F_t  = -S_t xi - gamma_t v_t, capped at mu F_n with the SLIDING friction mu
///          (the paper's eq. 8 tests against the rolling coefficient mu_0: a typo).
/// The normal force is clamped at zero: it never pulls (see docs/physics.md).
#include <algorithm>
#include <cmath>

#include "demlink/core/contact/contact_model.hpp"
#include "demlink/core/math_types.hpp"

namespace demlink::core {

/// The per-contact kernels are small and called from the innermost loops; GCC
/// does not inline them on its own (measured: 41 % of the deposition run was
/// spent in an out-of-line contactForce), so we insist.
#define DEMLINK_FORCE_INLINE inline __attribute__((always_inline))

/// Stiffness terms of a law at a given overlap.
struct ContactStiffness {
  double normal_elastic_force;  ///< F_ne [N]
  double normal_stiffness;      ///< S_n (tangent stiffness used for damping) [N/m]
  double tangential_stiffness;  ///< S_t [N/m]
};

struct HertzMindlinLaw {
  static constexpr ContactModel kModel = ContactModel::HertzMindlin;
  static ContactStiffness stiffness(const ContactPairParams& p, double rStar, double overlap) {
    const double root = std::sqrt(rStar * overlap);
    const double sn = 2.0 * p.effective_youngs * root;
    return {(2.0 / 3.0) * sn * overlap, sn, 8.0 * p.effective_shear * root};
  }
};

struct LinearSpringDashpotLaw {
  static constexpr ContactModel kModel = ContactModel::LinearSpringDashpot;
  static ContactStiffness stiffness(const ContactPairParams& p, double /*rStar*/, double overlap) {
    return {p.linear_normal_stiffness * overlap, p.linear_normal_stiffness, p.linear_tangential_stiffness};
  }
};

/// Force on B for one contact; updates the tangential history xi in place and
/// writes the (non-negative) normal force magnitude to normalForce.
template <class Law>
DEMLINK_FORCE_INLINE Vec3 contactForce(const ContactPairParams& p, const Vec3& n, double overlap, const Vec3& vRel,
                         double rStar, double mStar, double dt, Vec3& xi, double& normalForce) {
  const ContactStiffness k = Law::stiffness(p, rStar, overlap);
  const double vn = vRel.dot(n);  // < 0 while approaching
  const Vec3 vt = vRel - vn * n;
  const double dampingScale = std::sqrt(k.normal_stiffness * mStar);
  normalForce = std::max(0.0, k.normal_elastic_force - p.normal_damping * dampingScale * vn);

  // Keep the spring in the current tangent plane: drop its normal part and
  // restore its length (the contact frame has rotated, not the spring stretched).
  const double xiLength2 = xi.squaredNorm();
  if (xiLength2 > 0.0) {
    const double xn = xi.dot(n);
    const double tilt = xn * xn;  // = a |xi|^2, a = sin^2 of the spring's tilt out of the plane
    xi -= xn * n;
    if (tilt <= 1e-6 * xiLength2) {
      // Frames rotate little per step: 1/sqrt(1 - a) = 1 + a/2 + 3a^2/8 + O(a^3),
      // exact to ~1e-18 here, without the square root and division.
      const double a = tilt / xiLength2;
      xi *= 1.0 + a * (0.5 + 0.375 * a);
    } else {
      const double projected2 = xiLength2 - tilt;
      if (projected2 > 0.0) xi *= std::sqrt(xiLength2 / projected2);
    }
  }
  xi += vt * dt;

  const double gammaT = p.tangential_damping * dampingScale;
  Vec3 ft = -k.tangential_stiffness * xi - gammaT * vt;
  const double ftMax = p.sliding_friction * normalForce;
  const double ft2 = ft.squaredNorm();
  if (ft2 > ftMax * ftMax) {
    // Gross sliding: Coulomb force along the trial direction, and the spring alone
    // made to carry it. (Folding the damping term into the spring, as in
    // xi = -(F_t + gamma_t v_t)/S_t, stores a displacement opposite to the slip
    // while damping dominates; as S_t grows with the overlap that stored spring
    // then drives the slip instead of resisting it.)
    ft *= ftMax / std::sqrt(ft2);
    if (k.tangential_stiffness > 0.0) xi = -ft / k.tangential_stiffness;
  }
  return normalForce * n + ft;
}

/// EPSD rolling resistance: a constant torque mu_r R* F_n opposing the relative
/// rolling velocity (the tangential part of omega_B - omega_A). The magnitude is
/// limited so it can stop, but never reverse, the relative rolling within one
/// step (reducedInertia = (1/I_A + 1/I_B)^-1). Returns the torque ON B.
DEMLINK_FORCE_INLINE Vec3 rollingResistanceTorque(double rollingFriction, double rStar, double normalForce, const Vec3& n,
                                    const Vec3& omegaRel, double reducedInertia, double dt) {
  const Vec3 rolling = omegaRel - omegaRel.dot(n) * n;
  const double speed = rolling.norm();
  if (speed <= 0.0) return Vec3::Zero();
  const double magnitude = std::min(rollingFriction * rStar * normalForce, reducedInertia * speed / dt);
  return (-magnitude / speed) * rolling;
}

}  // namespace demlink::core
