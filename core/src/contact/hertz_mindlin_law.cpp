#include "demlink/core/contact/hertz_mindlin_law.hpp"

#include <cmath>

namespace demlink::core {

void HertzMindlinLaw::setPairCoefficients(ContactPairParams& p, double c, const Material& /*a*/,
                                          const Material& /*b*/, const LinearStiffnessReference& /*linearReference*/) {
  // Paper eq. 6: gamma_n = 2 sqrt(5/6) |beta| sqrt(S_n m*). The dimensionless ODE
  // coefficient is c = sqrt(5) |beta|, hence 2 sqrt(5/6) |beta| = c sqrt(2/3).
  p.normal_damping = c * std::sqrt(2.0 / 3.0);
  p.beta = -c / std::sqrt(5.0);
}

double HertzMindlinLaw::contactDuration(const ContactPairParams& p, double rStar, double mStar, double impactSpeed) {
  return 2.87 * std::pow(mStar * mStar / (rStar * p.effective_youngs * p.effective_youngs * impactSpeed), 0.2);
}

}  // namespace demlink::core
