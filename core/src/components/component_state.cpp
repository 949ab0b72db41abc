/// Checked reads and writes for component checkpoint state (see component_state.hpp).
#include "demlink/core/components/component_state.hpp"

#include <cmath>

#include "demlink/core/input_error.hpp"

namespace demlink::core {

void writeRandomState(StateWriter& out, const Random& rng) {
  const RandomState s = rng.state();
  for (std::uint64_t word : s.words) out.write(word);
  out.write(s.spare);
  out.write(static_cast<std::uint8_t>(s.has_spare));
}

RandomState readRandomState(StateReader& in) {
  RandomState s;
  bool allZero = true;
  for (std::uint64_t& word : s.words) {
    word = in.read<std::uint64_t>();
    allZero = allZero && word == 0;
  }
  if (allZero) in.fail("0 0 0 0", "random generator state is all zero (not a valid xoshiro256** state)");
  s.spare = readFinite(in, "random generator spare variate");
  s.has_spare = readFlag(in, "random generator spare flag");
  return s;
}

bool readFlag(StateReader& in, const std::string& what) {
  const auto flag = in.read<std::uint8_t>();
  if (flag > 1) in.fail(std::to_string(flag), what + " must be 0 or 1");
  return flag == 1;
}

double readNonNegative(StateReader& in, const std::string& what) {
  const double value = in.read<double>();
  if (!(std::isfinite(value) && value >= 0.0)) in.fail(formatValue(value), what + " must be finite and >= 0");
  return value;
}

double readFinite(StateReader& in, const std::string& what) {
  const double value = in.read<double>();
  if (!std::isfinite(value)) in.fail(formatValue(value), what + " must be finite");
  return value;
}

Vec3 readFiniteVector(StateReader& in, const std::string& what) {
  const Vec3 value = in.read<Vec3>();
  if (!value.allFinite()) in.fail("non-finite vector", what + " must be finite");
  return value;
}

void writeRemovalTally(StateWriter& out, const RemovalTally& tally) {
  out.write(tally.count);
  out.write(tally.mass);
}

RemovalTally readRemovalTally(StateReader& in, const std::string& what) {
  RemovalTally tally;
  tally.count = in.read<std::uint64_t>();
  tally.mass = readNonNegative(in, what + " mass");
  return tally;
}

StateReader componentSection(StateReader& in, std::string_view tag, const std::string& name) {
  return in.section(tag, in.sectionName() + "." + name);
}

}  // namespace demlink::core
