#include "demlink/core/particles/particle_arrays.hpp"

#include <map>
#include <numbers>
#include <string>
#include <type_traits>
#include <utility>

#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/particles/sphere.hpp"

namespace demlink::core {
namespace {

template <class T>
void permuteColumn(std::vector<T>& column, std::span<const std::uint32_t> oldSlotOfNew) {
  std::vector<T> reordered(oldSlotOfNew.size());
  for (std::size_t k = 0; k < oldSlotOfNew.size(); ++k) reordered[k] = column[oldSlotOfNew[k]];
  column.swap(reordered);
}

}  // namespace

void ParticleArrays::append(const ParticleSpec& spec, double density, std::uint64_t stableId) {
  const double m = sphereMass(spec.radius, density);
  position.push_back(spec.position);
  velocity.push_back(spec.velocity);
  angular_velocity.push_back(spec.angular_velocity);
  force.push_back(Vec3::Zero());
  torque.push_back(Vec3::Zero());
  radius.push_back(spec.radius);
  mass.push_back(m);
  inv_mass.push_back(1.0 / m);
  inv_inertia.push_back(1.0 / (0.4 * m * spec.radius * spec.radius));
  material.push_back(spec.material);
  id.push_back(stableId);
  clump_id.push_back(0);
}

void ParticleArrays::permute(std::span<const std::uint32_t> oldSlotOfNew) {
  forEachColumn([&](const char* /*name*/, auto& column) { permuteColumn(column, oldSlotOfNew); });
}

void ParticleArrays::reserve(std::size_t n) {
  forEachColumn([&](const char* /*name*/, auto& column) { column.reserve(n); });
}

void ParticleArrays::save(StateWriter& out) const {
  out.write<std::uint64_t>(size());
  std::uint32_t columns = 0;
  forEachColumn([&](const char*, const auto&) { ++columns; });
  out.write(columns);
  forEachColumn([&](const char* name, const auto& column) {
    using T = typename std::decay_t<decltype(column)>::value_type;
    out.section("COL ", [&] {
      out.writeString(name);
      out.write(static_cast<std::uint32_t>(StateCodec<T>::kBytes));
      out.writeVector(column);
    });
  });
}

void ParticleArrays::restore(StateReader& in) {
  const auto rows = in.read<std::uint64_t>();
  const auto columns = in.read<std::uint32_t>();
  std::map<std::string, std::pair<std::uint32_t, StateReader>> found;
  for (std::uint32_t c = 0; c < columns; ++c) {
    StateReader column = in.section("COL ", "particles.column[" + std::to_string(c) + "]");
    std::string name = column.readString();
    const auto bytes = column.read<std::uint32_t>();
    found.emplace(name, std::pair{bytes, StateReader(column)});
  }
  in.requireEnd();
  ParticleArrays staged;
  std::size_t used = 0;
  staged.forEachColumn([&](const char* name, auto& column) {
    using T = typename std::decay_t<decltype(column)>::value_type;
    const auto it = found.find(name);
    if (it == found.end()) in.fail(name, "particle column missing from the checkpoint");
    StateReader& data = it->second.second;
    if (it->second.first != StateCodec<T>::kBytes) {
      data.fail(std::to_string(it->second.first), std::string("element size of column ") + name + " should be " +
                                                      std::to_string(StateCodec<T>::kBytes));
    }
    column = data.readVector<T>();
    data.requireEnd();
    if (column.size() != rows) {
      data.fail(std::to_string(column.size()), std::string("column ") + name + " length differs from the " +
                                                   std::to_string(rows) + " particles");
    }
    ++used;
  });
  if (used != found.size()) {
    for (const auto& entry : found) {
      bool known = false;
      staged.forEachColumn([&](const char* name, const auto&) { known = known || entry.first == name; });
      if (!known) in.fail(entry.first, "particle column unknown to this engine (written by a newer version?)");
    }
  }
  *this = std::move(staged);
}

}  // namespace demlink::core
