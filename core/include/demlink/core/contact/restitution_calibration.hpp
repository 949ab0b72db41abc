#pragma once
/// Maps a requested coefficient of restitution to the damping coefficient that
/// delivers it, under DEMLink's convention that the normal contact force is never
/// attractive (clamped at zero; see docs/physics.md). The law-specific part, its
/// dimensionless normal ODE, is declared by each law; the integration and the
/// inversion here are shared.
///
/// Why calibrate: the closed form beta = ln e / sqrt(ln^2 e + pi^2) is exact only
/// for a linear spring-dashpot whose force may turn attractive. For Hertz with
/// damping gamma = 2 sqrt(5/6) |beta| sqrt(S_n m*) (solver paper eq. 6) the rebound
/// ratio differs from e by up to ~10 %, and clamping shifts it again. Every law
/// reduces to one dimensionless ODE with a single parameter c,
///   x'' = Law::dimensionlessAcceleration(x, x', c),  x(0) = 0, x'(0) = 1
/// (e.g. Hertz: x'' = -x^(3/2) - c x^(1/4) x'; linear: x'' = -x - c x').
/// The delivered restitution is the separation speed once the clamped force
/// vanishes. We integrate it (RK4, fine step) and invert e(c) by bisection, once
/// per requested e at set-up.
namespace demlink::core {

namespace restitution_detail {

struct State {
  double x;  // dimensionless overlap
  double v;  // dimensionless overlap rate (positive while approaching)
};

template <class Law>
double unclampedAcceleration(double c, const State& s) {
  return Law::dimensionlessAcceleration(s.x > 0.0 ? s.x : 0.0, s.v, c);
}

template <class Law>
State rk4Step(double c, const State& s, double h) {
  auto f = [&](const State& q) { return State{q.v, unclampedAcceleration<Law>(c, q)}; };
  const State k1 = f(s);
  const State k2 = f({s.x + 0.5 * h * k1.x, s.v + 0.5 * h * k1.v});
  const State k3 = f({s.x + 0.5 * h * k2.x, s.v + 0.5 * h * k2.v});
  const State k4 = f({s.x + h * k3.x, s.v + h * k3.v});
  return {s.x + h / 6.0 * (k1.x + 2.0 * k2.x + 2.0 * k3.x + k4.x),
          s.v + h / 6.0 * (k1.v + 2.0 * k2.v + 2.0 * k3.v + k4.v)};
}

}  // namespace restitution_detail

/// Rebound ratio delivered by Law's dimensionless damping coefficient c >= 0.
template <class Law>
double deliveredRestitution(double c) {
  using restitution_detail::State;
  // The undamped contact lasts ~3.2 (Hertz) or pi (linear) time units; 5e-5 gives
  // RK4 errors far below the 1e-6 we need. The contact ends when the clamped force
  // reaches zero (restoring term no longer beats damping) or the overlap closes.
  constexpr double kStep = 5.0e-5;
  State s{0.0, 1.0};
  for (int i = 0; i < 5'000'000; ++i) {
    State next = restitution_detail::rk4Step<Law>(c, s, kStep);
    if (next.x <= 0.0 || (next.v < 0.0 && restitution_detail::unclampedAcceleration<Law>(c, next) >= 0.0)) {
      return -next.v;
    }
    s = next;
  }
  return 0.0;  // overdamped: never separates within the horizon
}

/// The dimensionless damping coefficient c that makes `delivered` return e in
/// (0, 1], by bisection. Accurate to 1e-6 in e. e = 1 gives c = 0.
double dampingForRestitution(double e, double (*delivered)(double c));

/// The dimensionless damping coefficient c of Law that delivers restitution e.
template <class Law>
double dampingForRestitution(double e) {
  return dampingForRestitution(e, &deliveredRestitution<Law>);
}

}  // namespace demlink::core
