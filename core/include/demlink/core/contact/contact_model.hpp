#pragma once
/// User-facing choices of contact law and integrator, plus the per-material-pair
/// coefficients the laws read. Pairs are mixed once at set-up (ContactPairTable).
/// Each law lives in its own file (hertz_mindlin_law.hpp, ...); the registry
/// (contact_law_registry.hpp) maps a ContactModel value to it.
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace demlink::core {

enum class ContactModel : std::uint8_t {
  HertzMindlin,         ///< Hertz normal + Mindlin tangential (default, accurate)
  LinearSpringDashpot,  ///< constant stiffness (cheaper, restitution exact by construction)
};
/// Number of ContactModel values; they run 0 .. kContactModelCount - 1 (checkpoints
/// store the number, so values keep their place) and each has one registry entry.
inline constexpr std::size_t kContactModelCount = 2;

enum class IntegratorKind : std::uint8_t {
  VelocityVerlet,  ///< second order, symplectic (default)
  ExplicitEuler,   ///< the solver paper's eqs. 14-17: first order, gains energy; for comparison
};

/// The law's name in reports and run logs, e.g. "hertz_mindlin" (contact_law_registry.cpp).
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
  double cohesion_energy_density = 0.0;  ///< k_c [J/m^3]: cohesive force k_c A at overlap area A (0: dry)
  double linear_normal_stiffness = 0.0;      ///< k_n [N/m], linear law only
  double linear_tangential_stiffness = 0.0;  ///< k_t [N/m], linear law only
  double restitution = 1.0;           ///< requested e (for reports)
  double damping_coefficient = 0.0;   ///< the law's dimensionless c delivering e (for the time-step limit)
  double beta = 0.0;                  ///< solver-paper beta equivalent (Hertz) or -zeta (linear), for reports
};

/// The optional passes of one force-stage instantiation (contact_stage.hpp), fixed at
/// set-up so a scene that does not use one compiles it out.
struct ForcePasses {
  bool rolling = false;    ///< rolling-resistance torque
  bool cohesion = false;   ///< cohesive attraction k_c A (pairContactArea, wallContactArea)
  bool recording = false;  ///< contact records and triangle loads (contact_record.hpp)
};

/// Reference scales for the linear law's stiffness when the scene gives none:
/// k_n is chosen so a head-on impact of two reference spheres at the reference
/// speed reaches the same maximum overlap as under Hertz.
struct LinearStiffnessReference {
  double radius = 0.0;          ///< [m] reference particle radius (scene mean)
  double impact_velocity = 1.0; ///< [m/s]
  double normal_stiffness = 0.0;///< [N/m] if > 0, used as given for every pair
};

/// Tangential/normal stiffness ratio 4 G*/E* of a pair (Mindlin; 2(1-nu)/(2-nu) for
/// like materials). Both laws keep it; it also scales the tangential damping.
inline double tangentialStiffnessRatio(const ContactPairParams& p) {
  return 4.0 * p.effective_shear / p.effective_youngs;
}

}  // namespace demlink::core
