#pragma once
/// How large a time step keeps a damped contact's restitution within a
/// tolerance, found by integrating each law's dimensionless normal ODE
/// (restitution_calibration.hpp) with the engine's own integrator, step by step,
/// over many contact-onset phases.
///
/// Why: the discrete contact loses (or gains) rebound speed at first order in
/// dt / t_c, mostly at onset, where the damping term (Hertz: c x^(1/4) x') is not
/// smooth, and the loss depends on where between two steps the contact starts.
/// At dt = t_c / 100 the worst error over onset phases is ~2.8 % for e = 0.1 and
/// 0.02 % for e = 0.9 (velocity Verlet, Hertz), so a fixed number of steps per
/// contact cannot keep a promise for every e. Instead, for each requested e the
/// largest fraction f = dt / t_c (t_c: the elastic contact duration at the
/// impact speed, the law's contactDuration) whose worst error is within the
/// tolerance is found once at set-up and cached.
///
/// The discrete model matches World::step exactly for a head-on contact without
/// gravity: velocity Verlet computes the force at the drifted overlap with the
/// half-kicked velocity; explicit Euler drifts with the old velocity, kicks with
/// the old force and computes the force with the new velocity. The normal force
/// is clamped at zero, as in the kernel. Onset phase p in [0, 1): the step before
/// the contact ends a distance p * v dt short of touching.
///
/// Error measure: |e_delivered - e| / max(e, kRestitutionErrorFloor). For
/// e >= 0.1 it is the relative error; below, the same absolute error as at
/// e = 0.1 (a rebound-speed error of tolerance * 0.1 of the impact speed), since
/// a relative promise at e -> 0 would drive the step to zero.
#include <cstdint>

#include "demlink/core/contact/contact_model.hpp"

namespace demlink::core {

/// Below this e the tolerance is absolute: tolerance * kRestitutionErrorFloor.
inline constexpr double kRestitutionErrorFloor = 0.1;
/// Largest fraction of the contact duration ever accepted, whatever the
/// calibration says: fewer than 10 steps per contact leave tangential springs,
/// several simultaneous contacts and the skin check outside the single-contact
/// model the calibration checks.
inline constexpr double kMaxStepFractionOfContact = 0.1;
/// Onset phases sampled per fraction, (k + 1/2) / kOnsetPhases.
inline constexpr int kOnsetPhases = 64;
/// The calibration aims at this share of the tolerance, so phases between the
/// sampled ones stay within the tolerance itself.
inline constexpr double kPhaseSafety = 0.9;

namespace step_calibration_detail {

/// Rebound ratio delivered by the discrete integrator for Law's ODE with damping
/// c, dimensionless step h (time unit of the ODE) and onset phase in [0, 1).
template <class Law>
double discreteRestitution(double c, double h, double phase, IntegratorKind integrator) {
  auto force = [&](double x, double v) {  // clamped: never pulls
    if (x <= 0.0) return 0.0;
    const double a = Law::dimensionlessAcceleration(x, v, c);
    return a < 0.0 ? a : 0.0;
  };
  double x = -phase * h;  // overlap; the impact speed is 1
  double v = 1.0;
  double a = 0.0;
  bool touched = false;
  for (long i = 0; i < 100'000'000L; ++i) {
    if (integrator == IntegratorKind::VelocityVerlet) {
      v += 0.5 * h * a;
      x += h * v;
      a = force(x, v);
      v += 0.5 * h * a;
    } else {
      x += h * v;
      v += h * a;
      a = force(x, v);
    }
    if (x > 0.0) {
      touched = true;
    } else if (touched) {
      return -v;
    }
  }
  return 0.0;  // never separated
}

/// Dimensionless duration of Law's undamped contact (RK4 as in the calibration).
template <class Law>
double integrateElasticDuration() {
  constexpr double kStep = 5.0e-5;
  double x = 0.0;
  double v = 1.0;
  double t = 0.0;
  auto acc = [](double xx, double vv) { return Law::dimensionlessAcceleration(xx > 0.0 ? xx : 0.0, vv, 0.0); };
  for (int i = 0; i < 10'000'000; ++i) {
    const double k1x = v, k1v = acc(x, v);
    const double k2x = v + 0.5 * kStep * k1v, k2v = acc(x + 0.5 * kStep * k1x, v + 0.5 * kStep * k1v);
    const double k3x = v + 0.5 * kStep * k2v, k3v = acc(x + 0.5 * kStep * k2x, v + 0.5 * kStep * k2v);
    const double k4x = v + kStep * k3v, k4v = acc(x + kStep * k3x, v + kStep * k3v);
    const double xn = x + kStep / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
    const double vn = v + kStep / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    if (xn <= 0.0) return t + kStep * x / (x - xn);  // linear interpolation of the crossing
    x = xn;
    v = vn;
    t += kStep;
  }
  return t;
}

/// integrateElasticDuration, computed once per law.
template <class Law>
double elasticDuration() {
  static const double duration = integrateElasticDuration<Law>();
  return duration;
}

}  // namespace step_calibration_detail

/// Error measure of a delivered restitution against the requested e (see above).
double restitutionError(double delivered, double requested);

/// Worst restitutionError over kOnsetPhases onset phases at dt = fraction * t_c
/// (t_c the elastic contact duration), for the law of `model` with calibrated
/// damping c delivering e.
double worstRestitutionError(ContactModel model, IntegratorKind integrator, double e, double c, double fraction,
                             int phases = kOnsetPhases);

/// Largest fraction f <= kMaxStepFractionOfContact of the elastic contact
/// duration whose worst error over onset phases is within kPhaseSafety *
/// tolerance (bisection to 0.5 %, after a downward geometric scan, so no smaller
/// sampled fraction fails). Cached per (model, integrator, e, tolerance):
/// set-up pays ~10 ms per new requested e.
double accurateStepFraction(ContactModel model, IntegratorKind integrator, double e, double c, double tolerance);

}  // namespace demlink::core
