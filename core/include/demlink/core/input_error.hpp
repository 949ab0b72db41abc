#pragma once
/// Errors for bad user input (scene fields, files, parameters). Every error names
/// the offending field and its value so a user can fix the input without reading code.
#include <cmath>
#include <stdexcept>
#include <string>

namespace demlink::core {

/// Thrown when an input value is invalid. field() is a dotted path such as
/// "materials[2].youngs_modulus"; value() is the offending value as text.
class InputError : public std::runtime_error {
 public:
  InputError(std::string field, std::string value, const std::string& reason)
      : std::runtime_error(field + " = " + value + ": " + reason),
        field_(std::move(field)),
        value_(std::move(value)) {}

  [[nodiscard]] const std::string& field() const { return field_; }
  [[nodiscard]] const std::string& value() const { return value_; }

 private:
  std::string field_;
  std::string value_;
};

/// Formats a double for error messages with enough digits to be unambiguous.
std::string formatValue(double value);

/// Throws InputError unless value is finite.
void requireFinite(const std::string& field, double value);
/// Throws InputError unless value is finite and > 0.
void requirePositive(const std::string& field, double value);
/// Throws InputError unless value is finite and >= 0.
void requireNonNegative(const std::string& field, double value);
/// Throws InputError unless value is finite and lo < value < hi (open interval).
void requireOpenRange(const std::string& field, double value, double lo, double hi);
/// Throws InputError unless value is finite and lo < value <= hi.
void requireHalfOpenRange(const std::string& field, double value, double lo, double hi);

}  // namespace demlink::core
