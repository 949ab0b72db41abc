#pragma once
/// Critical time step of a scene: the largest step the world accepts without
/// allow_unsafe_time_step. It is the smallest of a list of constraints, each
/// named in the report:
///   rayleigh      kRayleighSafetyFraction * T_R of the smallest particle of each
///                 material, T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766);
///   restitution   per material pair, f(e) * t_c, where t_c is the pair's elastic
///                 contact duration at the validated impact speed (smallest
///                 particles; Hertz 2.87 (m*^2 / (R* E*^2 v))^(1/5), linear
///                 pi sqrt(m* / k_n)) and f(e) <= 0.1 the largest fraction whose
///                 restitution error over every contact-onset phase stays within
///                 restitution_tolerance with the engine's integrator
///                 (time_step_calibration.hpp);
///   others        appended by the world (addConstraint), e.g. deformable
///                 bodies' springs.
#include <string>
#include <vector>

#include "demlink/core/contact/contact_pair_table.hpp"
#include "demlink/core/materials/material.hpp"

namespace demlink::core {

inline constexpr double kRayleighSafetyFraction = 0.2;

/// One bound on the time step.
struct TimeStepConstraint {
  std::string name;    ///< "rayleigh", "restitution <a>/<b> (e = 0.5)", ...
  std::string detail;  ///< how it was computed, for the report
  double limit = 0.0;  ///< [s]
};

/// A material pair's calibrated damping and the step fraction its e allows.
struct PairDampingReport {
  std::string material_a;
  std::string material_b;
  double restitution = 1.0;         ///< requested e
  double damping_coefficient = 0.0; ///< the law's dimensionless c
  double beta = 0.0;                ///< solver-paper beta (Hertz) or -zeta (linear)
  double normal_damping = 0.0;      ///< gamma_n / sqrt(S_n m*)
  double tangential_damping = 0.0;  ///< gamma_t / sqrt(S_n m*)
  double step_fraction = 0.0;       ///< largest dt / t_c keeping e within the tolerance
  bool particle_pair = true;        ///< false: a wall material against particles
};

struct TimeStepReport {
  double rayleigh_time_step = 0.0;  ///< smallest T_R over the scene's particles [s]
  double contact_duration = 0.0;    ///< shortest elastic contact at the validated impact speed [s]
  double impact_speed = 0.0;        ///< validated impact speed [m/s]
  double restitution_tolerance = 0.0;
  double limit = 0.0;               ///< largest accepted time step [s] = min over constraints
  std::string limited_by;           ///< name of the constraint that set the limit
  std::vector<TimeStepConstraint> constraints;
  std::vector<PairDampingReport> damping;  ///< one per material pair a particle can meet

  /// Adds a constraint; limit and limited_by follow the smallest.
  void addConstraint(TimeStepConstraint constraint);
  /// Human-readable lines: the limit and what set it, every constraint, the damping table.
  [[nodiscard]] std::vector<std::string> describe() const;
};

/// A speed the world can see before it runs, and what moves at it.
struct SeenSpeed {
  std::string what;    ///< "particle 12", "particle_source feed", "mesh bucket", "frame rotation"
  double speed = 0.0;  ///< [m/s]
};

/// What World::initialize() found about the time step: the limits, the speeds the
/// scene shows before it runs (fastest first), and its warnings (a declared impact
/// speed below a seen one).
struct TimeStepCheck {
  TimeStepReport report;
  std::vector<SeenSpeed> seen_speeds;
  std::vector<std::string> warnings;
};

double rayleighTimeStep(const Material& m, double radius);

/// minRadiusOfMaterial[k] <= 0 means no particle uses material k (e.g. a wall
/// material); such materials enter only as wall partners. The restitution
/// constraint uses `integrator` and `restitutionTolerance`.
TimeStepReport criticalTimeStep(const std::vector<Material>& materials, const ContactPairTable& table,
                                ContactModel model, IntegratorKind integrator,
                                const std::vector<double>& minRadiusOfMaterial, double impactSpeed,
                                double restitutionTolerance);

}  // namespace demlink::core
