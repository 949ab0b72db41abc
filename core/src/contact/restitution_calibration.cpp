#include "demlink/core/contact/restitution_calibration.hpp"

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {

double dampingForRestitution(double e, double (*delivered)(double c)) {
  requireHalfOpenRange("restitution", e, 0.0, 1.0);
  if (e >= 1.0) return 0.0;
  double lo = 0.0;
  double hi = 1.0;
  while (delivered(hi) > e) hi *= 2.0;
  for (int i = 0; i < 60 && hi - lo > 1e-8 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (delivered(mid) > e) lo = mid; else hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace demlink::core
