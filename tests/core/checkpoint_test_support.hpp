#pragma once
// Shared by the checkpoint tests: save a world to bytes, and compare worlds bit
// for bit (NaN-safe, since memcmp compares representations).
#include <cstring>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "demlink/core/world.hpp"

namespace demlink::core::test {

inline std::string saveToBytes(const World& world) {
  std::ostringstream out;
  world.saveCheckpoint(out);
  return out.str();
}

template <class T>
bool bitEqual(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

/// Names of the particle columns that differ in any bit.
inline std::vector<std::string> differingColumns(const World& a, const World& b) {
  std::vector<std::string> differing;
  const ParticleArrays& pb = b.particles();
  a.particles().forEachColumn([&](const char* name, const auto& column) {
    pb.forEachColumn([&](const char* otherName, const auto& other) {
      if constexpr (std::is_same_v<decltype(column), decltype(other)>) {
        if (std::strcmp(name, otherName) == 0 && !bitEqual(column, other)) differing.emplace_back(name);
      }
    });
  });
  return differing;
}

}  // namespace demlink::core::test
