#pragma once
/// The contact kernel shared by every contact law: one function serves
/// particle-particle, particle-plane and particle-mesh contacts, so the force
/// law exists exactly once. A law (hertz_mindlin_law.hpp,
/// linear_spring_dashpot_law.hpp) is a compile-time type that supplies the
/// stiffness at an overlap; damping, the tangential spring, the Coulomb cap and
/// rolling resistance are common and live here.
///
/// Conventions for a contact between body A and body B:
///   n       unit normal from A towards B; the normal force on B is +F_n n.
///   delta   overlap > 0.
///   v_rel   velocity of B's contact point relative to A's.
///   xi      tangential spring (history): accumulated tangential displacement of
///           B relative to A, kept in the current tangent plane.
/// The returned vector is the force ON B; A receives its negative.
///
///   F_nd = gamma_n * (approach speed),  gamma_n = normal_damping * sqrt(S_n m*)
///   F_t  = -S_t xi - gamma_t v_t, capped at mu F_n with the SLIDING friction mu
///          (the solver paper's eq. 8 tests against the rolling coefficient mu_0: a typo).
/// The normal force is clamped at zero: it never pulls (see docs/physics.md).
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "demlink/core/contact/contact_model.hpp"
#include "demlink/core/base/math_types.hpp"

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

/// The terms of a contact that depend on its overlap alone: the law's stiffness and
/// the damping scale sqrt(S_n m*) [kg/s]. They end in a chain of square roots (the
/// centre distance, Hertz's sqrt(R* delta), the damping scale) that nothing else of
/// the contact needs before its normal force, so the pair loop computes them for a
/// batch of contacts first and lets the processor overlap the chains of several.
struct ContactElasticTerms {
  ContactStiffness stiffness;
  double damping_scale;  ///< sqrt(S_n m*) [kg/s]
};

template <class Law>
DEMLINK_FORCE_INLINE ContactElasticTerms contactElasticTerms(const ContactPairParams& p, double rStar, double mStar,
                                                             double overlap) {
  const ContactStiffness k = Law::stiffness(p, rStar, overlap);
  return {k, std::sqrt(k.normal_stiffness * mStar)};
}

/// Force on B for one contact of elastic terms `e` (contactElasticTerms); updates the
/// tangential history xi in place and writes the (non-negative) normal force magnitude
/// to normalForce.
template <class Law>
DEMLINK_FORCE_INLINE Vec3 contactForce(const ContactPairParams& p, const Vec3& n, const ContactElasticTerms& e,
                                       const Vec3& vRel, double dt, typename Law::History& xi, double& normalForce) {
  static_assert(std::is_same_v<typename Law::History, Vec3>, "the shared kernel keeps a tangential spring Vec3");
  const ContactStiffness& k = e.stiffness;
  const double dampingScale = e.damping_scale;
  const double vn = vRel.dot(n);  // < 0 while approaching
  const Vec3 vt = vRel - vn * n;
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

/// Force on B for one contact at `overlap` (reduced radius rStar [m], mass mStar [kg]);
/// updates xi and writes the normal force magnitude as above.
template <class Law>
DEMLINK_FORCE_INLINE Vec3 contactForce(const ContactPairParams& p, const Vec3& n, double overlap, const Vec3& vRel,
                                       double rStar, double mStar, double dt, typename Law::History& xi,
                                       double& normalForce) {
  return contactForce<Law>(p, n, contactElasticTerms<Law>(p, rStar, mStar, overlap), vRel, dt, xi, normalForce);
}

/// EPSD rolling resistance: a constant torque mu_r R* F_n opposing the relative
/// rolling velocity (the tangential part of omega_B - omega_A). The magnitude is
/// limited so it can stop, but never reverse, the relative rolling within one
/// step (the reduced inertia I* = (1/I_A + 1/I_B)^-1; inverseInertiaSum = 1/I_A + 1/I_B,
/// 1/I_A against a wall). Returns the torque ON B.
DEMLINK_FORCE_INLINE Vec3 rollingResistanceTorque(double rollingFriction, double rStar, double normalForce, const Vec3& n,
                                    const Vec3& omegaRel, double inverseInertiaSum, double dt) {
  const Vec3 rolling = omegaRel - omegaRel.dot(n) * n;
  const double speed2 = rolling.squaredNorm();
  if (speed2 <= 0.0) return Vec3::Zero();
  // |T| / speed = min(mu_r R* F_n / speed, I* / dt): one division after the square root
  // (the two limits divided by the speed apart), and I* / dt as one division off that
  // chain (a contact's divisions bound this pass).
  const double inverseSpeed = 1.0 / std::sqrt(speed2);
  const double stopping = 1.0 / (inverseInertiaSum * dt);
  return -std::min(rollingFriction * rStar * normalForce * inverseSpeed, stopping) * rolling;
}

}  // namespace demlink::core
