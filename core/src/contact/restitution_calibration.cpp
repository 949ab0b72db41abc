#include "demlink/core/contact/restitution_calibration.hpp"

#include <cmath>

#include "demlink/core/input_error.hpp"

namespace demlink::core {
namespace {

struct State {
  double x;  // dimensionless overlap
  double v;  // dimensionless overlap rate (positive while approaching)
};

double unclampedAcceleration(NormalLaw law, double c, const State& s) {
  const double x = s.x > 0.0 ? s.x : 0.0;
  if (law == NormalLaw::Hertz) return -x * std::sqrt(x) - c * std::sqrt(std::sqrt(x)) * s.v;
  return -x - c * s.v;
}

State rk4Step(NormalLaw law, double c, const State& s, double h) {
  auto f = [&](const State& q) { return State{q.v, unclampedAcceleration(law, c, q)}; };
  const State k1 = f(s);
  const State k2 = f({s.x + 0.5 * h * k1.x, s.v + 0.5 * h * k1.v});
  const State k3 = f({s.x + 0.5 * h * k2.x, s.v + 0.5 * h * k2.v});
  const State k4 = f({s.x + h * k3.x, s.v + h * k3.v});
  return {s.x + h / 6.0 * (k1.x + 2.0 * k2.x + 2.0 * k3.x + k4.x),
          s.v + h / 6.0 * (k1.v + 2.0 * k2.v + 2.0 * k3.v + k4.v)};
}

}  // namespace

double deliveredRestitution(NormalLaw law, double c) {
  // The undamped contact lasts ~3.2 (Hertz) or pi (linear) time units; 5e-5 gives
  // RK4 errors far below the 1e-6 we need. The contact ends when the clamped force
  // reaches zero (restoring term no longer beats damping) or the overlap closes.
  constexpr double kStep = 5.0e-5;
  State s{0.0, 1.0};
  for (int i = 0; i < 5'000'000; ++i) {
    State next = rk4Step(law, c, s, kStep);
    if (next.x <= 0.0 || (next.v < 0.0 && unclampedAcceleration(law, c, next) >= 0.0)) {
      return -next.v;
    }
    s = next;
  }
  return 0.0;  // overdamped: never separates within the horizon
}

double dampingForRestitution(NormalLaw law, double e) {
  requireHalfOpenRange("restitution", e, 0.0, 1.0);
  if (e >= 1.0) return 0.0;
  double lo = 0.0;
  double hi = 1.0;
  while (deliveredRestitution(law, hi) > e) hi *= 2.0;
  for (int i = 0; i < 60 && hi - lo > 1e-8 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (deliveredRestitution(law, mid) > e) lo = mid; else hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace demlink::core
