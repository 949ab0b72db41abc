#include "demlink/core/base/input_error.hpp"

#include <cstdio>

namespace demlink::core {

InputError::InputError(std::string field, std::string value, std::string reason)
    : std::runtime_error(field + " = " + value + ": " + reason),
      field_(std::move(field)),
      value_(std::move(value)),
      reason_(std::move(reason)) {}

InputError InputError::within(const std::string& path) const {
  if (path.empty()) return *this;
  if (field_.empty()) return InputError(path, value_, reason_);
  const bool indexed = field_.front() == '[';
  return InputError(path + (indexed ? "" : ".") + field_, value_, reason_);
}

InputError InputError::as(const std::string& field) const {
  if (field == field_ || field_.empty()) return InputError(field, value_, reason_);
  return InputError(field, value_, field_ + ": " + reason_);
}

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

void requireInRange(const std::string& field, double value, double lo, double hi, const std::string& unit) {
  requireFinite(field, value);
  if (!(value >= lo && value <= hi)) {
    throw InputError(field, formatValue(value),
                     "must lie in [" + formatValue(lo) + ", " + formatValue(hi) + "]" + (unit.empty() ? "" : " " + unit));
  }
}

}  // namespace demlink::core
