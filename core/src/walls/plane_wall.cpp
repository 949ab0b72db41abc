#include "demlink/core/walls/plane_wall.hpp"

#include <utility>

#include "demlink/core/state/state_stream.hpp"

namespace demlink::core {

void PlaneWall::buildNearList(const ParticleArrays& particles, double skin,
                              std::span<const std::uint32_t> newSlotOfOld) {
  const std::size_t n = particles.size();
  // Scatter old histories by their current slot, then gather into the new list.
  std::vector<Vec3> historyBySlot(n, Vec3::Zero());
  for (std::size_t k = 0; k < near_slots.size(); ++k) {
    const std::uint32_t slot = newSlotOfOld.empty() ? near_slots[k] : newSlotOfOld[near_slots[k]];
    if (slot != kRemovedSlot) historyBySlot[slot] = near_history[k];
  }
  near_slots.clear();
  near_history.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const double gap = (particles.position[i] - spec.point).dot(spec.normal) - particles.radius[i];
    if (gap < skin) {
      near_slots.push_back(static_cast<std::uint32_t>(i));
      near_history.push_back(historyBySlot[i]);
    }
  }
}

void PlaneWall::save(StateWriter& out) const {
  out.writeString(spec.name);
  out.writeVector(near_slots);
  out.writeVector(near_history);
  out.write(force);
  out.write(torque);
}

void PlaneWall::restore(StateReader& in, std::size_t slotCount) {
  const std::string name = in.readString();
  requireEqual(in, "plane name \"" + name + "\"", name, spec.name);
  std::vector<std::uint32_t> slots = in.readVector<std::uint32_t>();
  std::vector<Vec3> history = in.readVector<Vec3>();
  const auto wrenchForce = in.read<Vec3>();
  const auto wrenchTorque = in.read<Vec3>();
  requireIndices(in, slots, slotCount, "plane near-list slot");
  requireSameLength(in, history, slots, "plane histories and slots differ in length");
  near_slots = std::move(slots);
  near_history = std::move(history);
  force = wrenchForce;
  torque = wrenchTorque;
}

}  // namespace demlink::core
