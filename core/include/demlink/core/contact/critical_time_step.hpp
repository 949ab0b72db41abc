#pragma once
/// Critical time step of a scene: the Rayleigh time step of the smallest
/// particle of each material, and the contact duration of the smallest pair at
/// the user's maximum impact speed. DEMLink refuses a time step above
///   limit = min(kRayleighSafetyFraction * T_R, t_contact / kMinStepsPerContact)
/// unless the scene explicitly overrides the check.
///   T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766)
///   t_contact (Hertz) = 2.87 (m*^2 / (R* E*^2 v))^(1/5);  (linear) = pi sqrt(m* / k_n)
#include <string>
#include <vector>

#include "demlink/core/contact/contact_pair_table.hpp"
#include "demlink/core/materials/material.hpp"

namespace demlink::core {

inline constexpr double kRayleighSafetyFraction = 0.2;
inline constexpr double kMinStepsPerContact = 10.0;

struct TimeStepReport {
  double rayleigh_time_step = 0.0;  ///< smallest T_R over the scene's particles [s]
  double contact_duration = 0.0;    ///< shortest contact at the maximum impact speed [s]
  double limit = 0.0;               ///< largest accepted time step [s]
  std::string limited_by;           ///< "rayleigh" or "contact duration"
};

double rayleighTimeStep(const Material& m, double radius);

/// minRadiusOfMaterial[k] <= 0 means no particle uses material k (e.g. a wall
/// material); such materials enter only as wall partners.
TimeStepReport criticalTimeStep(const std::vector<Material>& materials, const ContactPairTable& table,
                                ContactModel model, const std::vector<double>& minRadiusOfMaterial,
                                double maxImpactVelocity);

}  // namespace demlink::core
