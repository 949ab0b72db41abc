#include "demlink/core/contact/linear_spring_dashpot_law.hpp"

#include <cmath>
#include <numbers>

#include "demlink/core/particles/sphere.hpp"

namespace demlink::core {
namespace {

/// Linear k_n matching Hertz's maximum overlap for two reference spheres:
/// delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5), and k_n = m* v^2 / delta_max^2.
double matchedLinearStiffness(const Material& a, const Material& b, double eStar,
                              const LinearStiffnessReference& ref) {
  if (ref.normal_stiffness > 0.0) return ref.normal_stiffness;
  const double ma = sphereMass(ref.radius, a.density);
  const double mb = sphereMass(ref.radius, b.density);
  const double mStar = ma * mb / (ma + mb);
  const double rStar = 0.5 * ref.radius;
  const double v = ref.impact_velocity;
  const double deltaMax = std::pow(15.0 * mStar * v * v / (16.0 * eStar * std::sqrt(rStar)), 0.4);
  return mStar * v * v / (deltaMax * deltaMax);
}

}  // namespace

void LinearSpringDashpotLaw::setPairCoefficients(ContactPairParams& p, double c, const Material& a,
                                                 const Material& b, const LinearStiffnessReference& linearReference) {
  // gamma_n = 2 zeta sqrt(k_n m*), with c = 2 zeta.
  p.normal_damping = c;
  p.beta = -0.5 * c;
  p.linear_normal_stiffness = matchedLinearStiffness(a, b, p.effective_youngs, linearReference);
  p.linear_tangential_stiffness = tangentialStiffnessRatio(p) * p.linear_normal_stiffness;
}

double LinearSpringDashpotLaw::contactDuration(const ContactPairParams& p, double /*rStar*/, double mStar,
                                               double /*impactSpeed*/) {
  return std::numbers::pi * std::sqrt(mStar / p.linear_normal_stiffness);
}

}  // namespace demlink::core
