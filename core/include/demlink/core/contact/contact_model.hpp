#pragma once
/// User-facing choices of contact law and integrator, plus the per-material-pair
/// coefficients both laws read. Pairs are mixed once at set-up (ContactPairTable).
#include <cstdint>
#include <string_view>

namespace demlink::core {

enum class ContactModel : std::uint8_t {
  HertzMindlin,         ///< Hertz normal + Mindlin tangential (default, accurate)
  LinearSpringDashpot,  ///< constant stiffness (cheaper, restitution exact by construction)
};

enum class IntegratorKind : std::uint8_t {
  VelocityVerlet,  ///< second order, symplectic (default)
  ExplicitEuler,   ///< the solver paper's eqs. 14-17: first order, gains energy; for comparison
};

std::string_view toString(ContactModel model);
std::string_view toString(IntegratorKind integrator);

/// Coefficients of one material pair, mixed once at set-up.
struct ContactPairParams {
  double effective_youngs = 0.0;      ///< E* [Pa] (solver paper eq. 3)
  double effective_shear = 0.0;       ///< G* [Pa] (eq. 4, corrected: (2 - nu)/G, not (1 - nu)/G)
  /// Normal damping gamma_n = normal_damping * sqrt(S_n m*), S_n the normal
  /// stiffness (Hertz: 2 E* sqrt(R* delta); linear: k_n). Calibrated so the
  /// delivered restitution equals the requested one (restitution_calibration.hpp).
  double normal_damping = 0.0;
  /// Tangential damping gamma_t = tangential_damping * sqrt(S_n m*) (includes sqrt(k_t/S_n)).
  double tangential_damping = 0.0;
  double sliding_friction = 0.0;      ///< mu [-]
  double rolling_friction = 0.0;      ///< mu_r [-]
  double linear_normal_stiffness = 0.0;      ///< k_n [N/m], linear law only
  double linear_tangential_stiffness = 0.0;  ///< k_t [N/m], linear law only
  double restitution = 1.0;           ///< requested e (for reports)
  double beta = 0.0;                  ///< solver-paper beta equivalent (Hertz) or -zeta (linear), for reports
};

}  // namespace demlink::core
