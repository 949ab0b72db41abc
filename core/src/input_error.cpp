#include "demlink/core/input_error.hpp"

#include <cstdio>

namespace demlink::core {

std::string formatValue(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

void requireFinite(const std::string& field, double value) {
  if (!std::isfinite(value)) throw InputError(field, formatValue(value), "must be a finite number");
}

void requirePositive(const std::string& field, double value) {
  requireFinite(field, value);
  if (!(value > 0.0)) throw InputError(field, formatValue(value), "must be > 0");
}

void requireNonNegative(const std::string& field, double value) {
  requireFinite(field, value);
  if (!(value >= 0.0)) throw InputError(field, formatValue(value), "must be >= 0");
}

void requireOpenRange(const std::string& field, double value, double lo, double hi) {
  requireFinite(field, value);
  if (!(value > lo && value < hi)) {
    throw InputError(field, formatValue(value),
                     "must lie in the open interval (" + formatValue(lo) + ", " + formatValue(hi) + ")");
  }
}

void requireHalfOpenRange(const std::string& field, double value, double lo, double hi) {
  requireFinite(field, value);
  if (!(value > lo && value <= hi)) {
    throw InputError(field, formatValue(value),
                     "must lie in (" + formatValue(lo) + ", " + formatValue(hi) + "]");
  }
}

}  // namespace demlink::core
