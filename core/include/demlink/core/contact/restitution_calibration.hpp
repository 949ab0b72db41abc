#pragma once
/// Maps a requested coefficient of restitution to the damping coefficient that
/// delivers it, for each normal contact law, under DEMLink's convention that the
/// normal contact force is never attractive (clamped at zero; see docs/physics.md).
///
/// Why calibrate: the closed form beta = ln e / sqrt(ln^2 e + pi^2) is exact only
/// for a linear spring-dashpot whose force may turn attractive. For Hertz with
/// damping gamma = 2 sqrt(5/6) |beta| sqrt(S_n m*) (solver paper eq. 6) the rebound
/// ratio differs from e by up to ~10 %, and clamping shifts it again. Both laws
/// reduce to one dimensionless ODE with a single parameter c:
///   Hertz:   x'' = -x^(3/2) - c x^(1/4) x'      (c = sqrt(5) |beta|)
///   linear:  x'' = -x       - c x'              (c = 2 zeta)
/// with x(0) = 0, x'(0) = 1. The delivered restitution is the separation speed
/// once the clamped force vanishes. We integrate it (RK4, fine step) and invert
/// e(c) by bisection, once per material pair at set-up.
namespace demlink::core {

enum class NormalLaw { Hertz, Linear };

/// Rebound ratio delivered by the dimensionless damping coefficient c >= 0.
double deliveredRestitution(NormalLaw law, double c);

/// The dimensionless damping coefficient c that delivers restitution e in (0, 1].
/// Accurate to 1e-6 in e. e = 1 gives c = 0.
double dampingForRestitution(NormalLaw law, double e);

}  // namespace demlink::core
