#pragma once
/// Errors for bad user input (scene fields, files, parameters). Every error names
/// the offending field and its value so a user can fix the input without reading code.
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace demlink::core {

/// Thrown when an input value is invalid. field() is a dotted path such as
/// "youngs_modulus" or, once a translator has put the scene path in front
/// (within()), "materials[2].youngs_modulus"; value() is the offending value as text;
/// reason() says what is wrong. what() is "<field> = <value>: <reason>", formatted
/// here and nowhere else: code that needs a part asks for it, never parses what().
class InputError : public std::runtime_error {
 public:
  InputError(std::string field, std::string value, std::string reason);

  [[nodiscard]] const std::string& field() const { return field_; }
  [[nodiscard]] const std::string& value() const { return value_; }
  [[nodiscard]] const std::string& reason() const { return reason_; }

  /// The same error with `path` in front of the field ("simulation_box" + "time_step"
  /// -> "simulation_box.time_step"; "materials" + "[2].name" -> "materials[2].name";
  /// an empty field becomes `path`).
  [[nodiscard]] InputError within(const std::string& path) const;
  /// The same error named by `field` instead: for a field that names a file whose content
  /// is wrong. The old field (the place inside the file) goes into the reason, once.
  [[nodiscard]] InputError as(const std::string& field) const;

 private:
  std::string field_;
  std::string value_;
  std::string reason_;
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
/// The check for every duration and bounded quantity: throws InputError unless value is
/// finite and lo <= value <= hi; `unit` (e.g. "s") follows the bounds in the reason.
void requireInRange(const std::string& field, double value, double lo, double hi, const std::string& unit = "");

}  // namespace demlink::core
