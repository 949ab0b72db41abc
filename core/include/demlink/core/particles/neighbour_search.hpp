#pragma once
/// The particles' neighbour search between builds: the Verlet list with its carried
/// histories, the guard that says when it may have missed a contact, whether a
/// rebuild is due anyway (slots changed), and the slot map since the last build.
#include <cstdint>
#include <vector>

#include "demlink/core/particles/neighbour_list.hpp"
#include "demlink/core/particles/rebuild_guard.hpp"

namespace demlink::core {

struct NeighbourSearch {
  NeighbourList list;
  RebuildGuard guard;  ///< armed by every build and restore
  bool rebuild_pending = true;
  /// Slot of every particle of the last build in the current numbering (empty:
  /// unchanged). Composed across removals and sorts until the next build.
  std::vector<std::uint32_t> pending_new_slot_of_old;
};

}  // namespace demlink::core
