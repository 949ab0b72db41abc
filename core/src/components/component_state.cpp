/// Checked reads and writes for component checkpoint state (see component_state.hpp).
#include "demlink/core/components/component_state.hpp"

#include <cmath>

#include "demlink/core/base/input_error.hpp"

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

void saveComponents(StateWriter& out, const std::vector<std::unique_ptr<WorldComponent>>& components) {
  out.write<std::uint64_t>(components.size());
  for (const auto& component : components) {
    out.writeString(component->name());
    out.writeString(component->kind());
    out.section("DATA", [&] { component->saveState(out); });
  }
}

std::vector<StateReader> readComponentSections(StateReader& in,
                                               const std::vector<std::unique_ptr<WorldComponent>>& components) {
  readMatchingCount(in, "component", components.size());
  std::vector<StateReader> data;
  for (const auto& component : components) {
    const std::string name = in.readString();
    const std::string kind = in.readString();
    requireEqual(in, "component \"" + name + "\"", name, component->name());
    requireEqual(in, "kind \"" + kind + "\" of component \"" + name + "\"", kind, std::string(component->kind()));
    data.push_back(in.section("DATA", "components." + name));
  }
  in.requireEnd();
  return data;
}

void restoreComponents(const std::vector<std::unique_ptr<WorldComponent>>& components,
                       std::vector<StateReader>& data, const std::string& source,
                       std::vector<std::optional<StateReader>>* inputs) {
  std::vector<std::string> previous;
  std::vector<std::string> previousInputs;
  for (const auto& component : components) {
    StateWriter backup;
    component->saveState(backup);
    previous.push_back(backup.bytes());
    StateWriter inputBackup;
    component->saveInputs(inputBackup);
    previousInputs.push_back(inputBackup.bytes());
  }
  try {
    for (std::size_t k = 0; k < components.size(); ++k) {
      components[k]->loadState(data[k]);
      data[k].requireEnd();
      if (inputs != nullptr && (*inputs)[k]) {
        components[k]->loadInputs(*(*inputs)[k]);
        (*inputs)[k]->requireEnd();
      }
    }
  } catch (...) {
    for (std::size_t k = 0; k < components.size(); ++k) {
      StateReader backup(previous[k], source, "components." + components[k]->name());
      components[k]->loadState(backup);
      if (inputs != nullptr && (*inputs)[k]) {
        StateReader inputBackup(previousInputs[k], source, "inputs." + components[k]->name());
        components[k]->loadInputs(inputBackup);
      }
    }
    throw;
  }
}

void writeRegionInputs(StateWriter& out, const VolumeShape& shape, const RegionPlacement& placement) {
  const bool box = shape.kind() == VolumeShape::Kind::Box;
  out.write(static_cast<std::uint8_t>(box));
  out.write<Vec3>(box ? Vec3(2.0 * shape.halfSides()) : Vec3(shape.radius(), 0.0, 0.0));
  out.write<Vec3>(placement.centre);
  const Quat& q = placement.orientation;
  out.write<Vec3>(Vec3(q.x(), q.y(), q.z()));
  out.write(q.w());
}

void readRegionInputs(StateReader& in, VolumeShape& shape, RegionPlacement& placement) {
  const bool box = readFlag(in, "region shape flag");
  if (box != (shape.kind() == VolumeShape::Kind::Box)) {
    in.fail(box ? "box" : "sphere", "the region's shape differs from the scene's");
  }
  const Vec3 size = readFiniteVector(in, "region size");
  const Vec3 centre = readFiniteVector(in, "region centre");
  const Vec3 xyz = readFiniteVector(in, "region orientation");
  const double w = readFinite(in, "region orientation w");
  const Quat orientation(w, xyz.x(), xyz.y(), xyz.z());
  if (std::abs(orientation.norm() - 1.0) > 1e-9) {
    in.fail(formatValue(orientation.norm()), "the region orientation is not a unit quaternion");
  }
  if (!(box ? (size.array() > 0.0).all() : size.x() > 0.0)) in.fail(formatValue(box ? size.minCoeff() : size.x()), "region size must be > 0");
  shape = box ? VolumeShape::box(size, "region") : VolumeShape::sphere(size.x(), "region");
  placement.centre = centre;
  placement.orientation = orientation;
}

bool anyInputsChanged(const std::vector<std::unique_ptr<WorldComponent>>& components) {
  for (const auto& component : components) {
    if (component->inputsChanged()) return true;
  }
  return false;
}

void saveComponentInputs(StateWriter& out, const std::vector<std::unique_ptr<WorldComponent>>& components) {
  std::uint64_t count = 0;
  for (const auto& component : components) count += component->inputsChanged() ? 1 : 0;
  out.write(count);
  for (const auto& component : components) {
    if (!component->inputsChanged()) continue;
    out.writeString(component->name());
    out.section("DATA", [&] { component->saveInputs(out); });
  }
}

std::vector<std::optional<StateReader>> readComponentInputs(
    StateReader& in, const std::vector<std::unique_ptr<WorldComponent>>& components) {
  std::vector<std::optional<StateReader>> inputs(components.size());
  const auto count = in.read<std::uint64_t>();
  if (count > components.size()) {
    in.fail(std::to_string(count), "more components with inputs than the scene has (" +
                                       std::to_string(components.size()) + ")");
  }
  for (std::uint64_t n = 0; n < count; ++n) {
    const std::string name = in.readString();
    std::size_t k = 0;
    while (k < components.size() && components[k]->name() != name) ++k;
    if (k == components.size()) in.fail("\"" + name + "\"", "no component of the scene has this name");
    if (inputs[k]) in.fail("\"" + name + "\"", "the component's inputs are listed twice");
    inputs[k].emplace(in.section("DATA", "inputs." + name));
  }
  in.requireEnd();
  return inputs;
}

}  // namespace demlink::core
