#include "demlink/core/walls/mesh_near_list.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/geometry/triangle_geometry.hpp"

namespace demlink::core {

void MeshNearList::build(const ParticleArrays& particles, std::span<const Vec3> vertices,
                         std::span<const std::array<std::uint32_t, 3>> tris, std::span<const char> active,
                         const CellGrid& grid, double skin, std::span<const std::uint32_t> newSlotOfOld) {
  // Old histories keyed by (current slot, triangle); only touching ones matter.
  std::map<std::pair<std::uint32_t, std::uint32_t>, Vec3> carried;
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const std::uint32_t slot = newSlotOfOld.empty() ? slots[k] : newSlotOfOld[slots[k]];
    if (slot == kRemovedSlot) continue;
    for (std::uint32_t c = offsets[k]; c < offsets[k + 1]; ++c) {
      if (!history[c].isZero(0.0)) carried.emplace(std::make_pair(slot, triangles[c]), history[c]);
    }
  }

  const std::size_t n = particles.size();
  std::vector<std::vector<std::uint32_t>> candidatesOf(n);
  if (n > 0) {
    const double maxRadius = *std::max_element(particles.radius.begin(), particles.radius.end());
    const double reach = maxRadius + skin;
    for (std::uint32_t t = 0; t < tris.size(); ++t) {
      if (!active.empty() && active[t] == 0) continue;
      const Vec3& a = vertices[tris[t][0]];
      const Vec3& b = vertices[tris[t][1]];
      const Vec3& c = vertices[tris[t][2]];
      const Vec3 lo = a.cwiseMin(b).cwiseMin(c) - Vec3::Constant(reach);
      const Vec3 hi = a.cwiseMax(b).cwiseMax(c) + Vec3::Constant(reach);
      grid.forEachInBox(lo, hi, [&](std::uint32_t i) {
        const Vec3& x = particles.position[i];
        const double limit = particles.radius[i] + skin;
        if ((x - closestPointOnTriangle(x, a, b, c).point).squaredNorm() < limit * limit) candidatesOf[i].push_back(t);
      });
    }
  }

  slots.clear();
  offsets.assign(1, 0);
  triangles.clear();
  history.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    if (candidatesOf[i].empty()) continue;
    std::sort(candidatesOf[i].begin(), candidatesOf[i].end());
    slots.push_back(i);
    for (const std::uint32_t t : candidatesOf[i]) {
      triangles.push_back(t);
      const auto it = carried.find({i, t});
      history.push_back(it == carried.end() ? Vec3::Zero() : it->second);
    }
    offsets.push_back(static_cast<std::uint32_t>(triangles.size()));
  }
}

void MeshNearList::save(StateWriter& out) const {
  out.writeVector(slots);
  out.writeVector(offsets);
  out.writeVector(triangles);
  out.writeVector(history);
}

void MeshNearList::restore(StateReader& in, std::size_t slotCount, std::size_t triangleCount) {
  MeshNearList staged;
  staged.slots = in.readVector<std::uint32_t>();
  staged.offsets = in.readVector<std::uint32_t>();
  staged.triangles = in.readVector<std::uint32_t>();
  staged.history = in.readVector<Vec3>();
  requireIndices(in, staged.slots, slotCount, "mesh near-list slot");
  requireIndices(in, staged.triangles, triangleCount, "mesh near-list triangle");
  requireOffsets(in, staged.offsets, staged.triangles.size(), "mesh near-list offsets");
  if (staged.offsets.size() != staged.slots.size() + 1) {
    in.fail(std::to_string(staged.offsets.size()), "mesh near-list offsets do not match its slots");
  }
  requireSameLength(in, staged.history, staged.triangles, "mesh histories and candidates differ in length");
  // The force stage finds each pair-loop chunk's entries by slot and each contact's spring
  // by triangle (binary searches), so both orders are part of the list.
  const auto notAscending = [](const auto first, const auto last) {
    return std::adjacent_find(first, last, [](std::uint32_t a, std::uint32_t b) { return a >= b; }) != last;
  };
  if (notAscending(staged.slots.begin(), staged.slots.end())) {
    in.fail("slots", "mesh near-list slots are not strictly ascending");
  }
  for (std::size_t k = 0; k < staged.slots.size(); ++k) {
    const auto row = staged.triangles.begin();
    if (notAscending(row + staged.offsets[k], row + staged.offsets[k + 1])) {
      in.fail("triangles of slot " + std::to_string(staged.slots[k]),
              "mesh near-list triangles are not strictly ascending");
    }
  }
  *this = std::move(staged);
}

}  // namespace demlink::core
