#pragma once
/// Verlet neighbour list with a skin, as a half list in compressed rows: the
/// partners of slot i are partners[offsets[i] .. offsets[i+1]), all > i, within
/// r_i + r_j + skin at build time. World rebuilds it when a pair may have closed
/// the skin unseen: RebuildGuard watches relative displacements, needsRebuild() the
/// classic rule (some particle moved more than skin/2). Each pair carries its
/// tangential history; a rebuild carries it over, also when slots were compacted or
/// reordered in between.
#include <cstdint>
#include <span>
#include <vector>

#include "demlink/core/particles/cell_grid.hpp"
#include "demlink/core/base/math_types.hpp"
#include "demlink/core/particles/particle_arrays.hpp"
#include "demlink/core/parallel/thread_pool.hpp"

namespace demlink::core {

class StateWriter;
class StateReader;

/// Effective radius and mass of a listed pair, fixed for the pair's lifetime in
/// the list (particle radii and masses do not change), so the force loop does not
/// divide for them at every step.
struct ReducedPair {
  double radius;  ///< R* = r_i r_j / (r_i + r_j) [m]
  double mass;    ///< m* = m_i m_j / (m_i + m_j) [kg]
};

class NeighbourList {
 public:
  explicit NeighbourList(double skin = 0.0) : skin_(skin) {}

  [[nodiscard]] double skin() const { return skin_; }

  /// True when the largest displacement since the last build exceeds skin/2.
  [[nodiscard]] bool needsRebuild(std::span<const Vec3> positions, ThreadPool* pool = nullptr) const;

  /// Rebuilds the list. newSlotOfOld maps every slot of the previous build to its
  /// current slot (kRemovedSlot if removed); empty means slots are unchanged.
  /// excludeSameClump: leave out pairs of spheres of the same clump (equal
  /// non-zero clump_id); false compiles the search without the test.
  void build(const ParticleArrays& particles, std::span<const std::uint32_t> newSlotOfOld,
             ThreadPool* pool = nullptr, bool excludeSameClump = false);

  [[nodiscard]] std::span<const std::uint32_t> offsets() const { return offsets_; }
  [[nodiscard]] std::span<const std::uint32_t> partners() const { return partners_; }
  /// The row (slot i) of each listed pair: rows()[k] = i for offsets()[i] <= k < offsets()[i+1],
  /// so a loop can walk the pairs of many rows as one sequence.
  [[nodiscard]] std::span<const std::uint32_t> rows() const { return rows_; }
  [[nodiscard]] std::span<const ReducedPair> reduced() const { return reduced_; }
  [[nodiscard]] std::span<Vec3> history() { return history_; }
  [[nodiscard]] std::span<const Vec3> history() const { return history_; }
  /// Per pair, 1 where its history may be non-zero: the pair touched at the last force
  /// evaluation, or was carried over with a spring by the last build. The pair loop keeps
  /// it, so pairs that stay apart cost one byte, not their 24-byte history.
  [[nodiscard]] std::span<std::uint8_t> sprung() { return sprung_; }
  [[nodiscard]] std::size_t pairCount() const { return partners_.size(); }
  /// Rows (particle slots) of the last build.
  [[nodiscard]] std::size_t rowCount() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  [[nodiscard]] std::uint64_t buildCount() const { return builds_; }
  /// Positions of the last build, one per row.
  [[nodiscard]] std::span<const Vec3> builtPositions() const { return position_at_build_; }
  [[nodiscard]] const CellGrid& grid() const { return grid_; }
  /// Bytes held by the list and its grid (capacities).
  [[nodiscard]] std::size_t bytes() const;

  /// Checkpoint payload (section NBRL): skin, build count (decides the next
  /// re-sort), offsets, partners, tangential histories, reduced pair data and the
  /// positions of the last build (decide the next rebuild). The cell grid is not
  /// saved: every build makes it anew.
  void save(StateWriter& out) const;
  /// Replaces the list with what save() wrote. The saved skin must equal this
  /// list's; offsets, partner indices and array lengths must be consistent
  /// (throws InputError via in.fail() otherwise).
  void restore(StateReader& in);

 private:
  double skin_;
  std::uint64_t builds_ = 0;
  CellGrid grid_;
  std::vector<std::uint32_t> offsets_{0};
  std::vector<std::uint32_t> partners_;
  std::vector<std::uint32_t> rows_;  ///< derived from offsets_ (not saved)
  std::vector<Vec3> history_;
  std::vector<std::uint8_t> sprung_;  ///< derived from history_ by build() and restore() (not saved)
  std::vector<ReducedPair> reduced_;
  std::vector<Vec3> position_at_build_;
};

}  // namespace demlink::core
