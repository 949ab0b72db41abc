#pragma once
/// Linear spring-dashpot contact law (cheaper alternative): everything
/// particular to it — the stiffness, its restitution calibration, its pair
/// coefficients (including the stiffness matched to Hertz), its contact duration
/// and the per-contact history it keeps. The force itself is the shared kernel
/// contactForce<LinearSpringDashpotLaw> (contact_kernel.hpp).
///
///   F_ne = k_n delta, S_t = k_t = (4 G*/E*) k_n,  gamma_n = 2 zeta sqrt(k_n m*)
/// k_n, unless the scene gives one, matches Hertz's maximum overlap for two
/// reference spheres: delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5), k_n = m* v^2 / delta_max^2.
/// Restitution: the damped normal motion is x'' = -x - c x' with c = 2 zeta
/// (restitution_calibration.hpp). Contact duration: t_c = pi sqrt(m* / k_n).
#include <string_view>

#include "demlink/core/contact/contact_kernel.hpp"
#include "demlink/core/contact/contact_model.hpp"
#include "demlink/core/materials/material.hpp"
#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

struct LinearSpringDashpotLaw {
  static constexpr ContactModel kModel = ContactModel::LinearSpringDashpot;
  static constexpr std::string_view kName = "linear_spring_dashpot";
  /// Per-contact history: the tangential spring xi [m] (contact_kernel.hpp).
  using History = Vec3;
  /// F_ne grows as overlap^kForceExponent: the stored elastic energy is F_ne delta / (kForceExponent + 1).
  static constexpr double kForceExponent = 1.0;

  static ContactStiffness stiffness(const ContactPairParams& p, double /*rStar*/, double overlap) {
    return {p.linear_normal_stiffness * overlap, p.linear_normal_stiffness, p.linear_tangential_stiffness};
  }

  /// Dimensionless normal ODE x'' at overlap x >= 0 and approach rate v.
  static double dimensionlessAcceleration(double x, double v, double c) { return -x - c * v; }

  /// Damping, the equivalent beta (-zeta) and the stiffnesses k_n, k_t of a pair from the calibrated c.
  static void setPairCoefficients(ContactPairParams& p, double c, const Material& a, const Material& b,
                                  const LinearStiffnessReference& linearReference);

  /// Duration [s] of a head-on impact (independent of the speed for a linear spring).
  static double contactDuration(const ContactPairParams& p, double rStar, double mStar, double impactSpeed);
};

}  // namespace demlink::core
