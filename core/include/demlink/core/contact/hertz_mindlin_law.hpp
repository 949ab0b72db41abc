#pragma once
/// Hertz-Mindlin contact law (the default): everything particular to it — the
/// stiffness at an overlap, its restitution calibration, its pair coefficients,
/// its contact duration and the per-contact history it keeps. The force itself
/// is the shared kernel contactForce<HertzMindlinLaw> (contact_kernel.hpp).
///
/// Solver paper eqs. 5-8, corrected:
///   S_n = 2 E* sqrt(R* delta),   F_ne = 4/3 E* sqrt(R*) delta^(3/2) = 2/3 S_n delta
///   S_t = 8 G* sqrt(R* delta)    (the paper writes sqrt(R* delta_t); it is the normal overlap)
///   gamma_n = 2 sqrt(5/6) |beta| sqrt(S_n m*)  (the paper omits the square root on S_n m*)
/// Restitution: with x = delta / delta_scale and time in units of the contact
/// time scale, the damped normal motion is x'' = -x^(3/2) - c x^(1/4) x' with
/// c = sqrt(5) |beta| (restitution_calibration.hpp).
/// Contact duration at impact speed v: t_c = 2.87 (m*^2 / (R* E*^2 v))^(1/5).
#include <cmath>
#include <string_view>

#include "demlink/core/contact/contact_kernel.hpp"
#include "demlink/core/contact/contact_model.hpp"
#include "demlink/core/materials/material.hpp"
#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

struct HertzMindlinLaw {
  static constexpr ContactModel kModel = ContactModel::HertzMindlin;
  static constexpr std::string_view kName = "hertz_mindlin";
  /// Per-contact history: the tangential spring xi [m] (contact_kernel.hpp).
  using History = Vec3;
  /// F_ne grows as overlap^kForceExponent: the stored elastic energy is F_ne delta / (kForceExponent + 1).
  static constexpr double kForceExponent = 1.5;

  static ContactStiffness stiffness(const ContactPairParams& p, double rStar, double overlap) {
    const double root = std::sqrt(rStar * overlap);
    const double sn = 2.0 * p.effective_youngs * root;
    return {(2.0 / 3.0) * sn * overlap, sn, 8.0 * p.effective_shear * root};
  }

  /// Dimensionless normal ODE x'' at overlap x >= 0 and approach rate v.
  static double dimensionlessAcceleration(double x, double v, double c) {
    return -x * std::sqrt(x) - c * std::sqrt(std::sqrt(x)) * v;
  }

  /// Damping coefficients (and the equivalent beta) of a pair from the calibrated c.
  static void setPairCoefficients(ContactPairParams& p, double c, const Material& a, const Material& b,
                                  const LinearStiffnessReference& linearReference);

  /// Duration [s] of a head-on impact at impactSpeed [m/s] (reduced radius rStar [m], mass mStar [kg]).
  static double contactDuration(const ContactPairParams& p, double rStar, double mStar, double impactSpeed);
};

}  // namespace demlink::core
