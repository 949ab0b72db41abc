#include "demlink/core/step/pair_loop_partition.hpp"

#include <algorithm>

namespace demlink::core {
namespace {

/// The chunk windows together may hold 3/2 slots per row (plus a constant): with force
/// and torque that is at most ~72 bytes per particle.
constexpr std::size_t kWindowSlotsPerTwoRows = 3;
constexpr std::size_t kMaxChunksPlanned = 4096;

}  // namespace

void PairLoopPartition::plan(std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> partners,
                             std::uint32_t threads) {
  const std::size_t rows = offsets.empty() ? 0 : offsets.size() - 1;
  const std::uint64_t pairs = offsets.empty() ? 0 : offsets.back();
  // About kPairsPerChunk pairs per chunk, but at least 16 chunks of >= 64 rows, so a
  // small scene still has chunks to share; fewer when the windows grow too wide.
  std::size_t wanted = std::max<std::size_t>(static_cast<std::size_t>(pairs / kPairsPerChunk),
                                             std::min<std::size_t>(16, rows / 64));
  wanted = threads <= 1 ? 1 : std::clamp<std::size_t>(wanted, 1, kMaxChunksPlanned);
  // Too wide windows: a quarter fewer chunks at a time, so the count that fits is near the
  // largest one that does (halving could lose nearly half of the chunks that fit). Then an
  // even count from 4 on: two threads' home ranges hold as many chunks each (9 chunks of
  // a 50,000-bed gave one thread 5/9 of the pairs; a thread that has claimed its last
  // chunk leaves nothing to steal).
  bool evened = false;
  for (;;) {
    const std::size_t chunks = rows == 0 ? 0 : wanted;
    row_begin_.assign(chunks + 1, rows);
    row_begin_[0] = 0;
    for (std::size_t c = 1; c < chunks; ++c) {
      // First row whose pair offset reaches c/chunks of all pairs.
      const std::uint64_t target = pairs * c / chunks;
      const auto it = std::lower_bound(offsets.begin(), offsets.begin() + static_cast<std::ptrdiff_t>(rows), target);
      row_begin_[c] = std::max(row_begin_[c - 1], static_cast<std::size_t>(it - offsets.begin()));
    }
    // Chunks left without rows by a row holding many pairs are dropped.
    row_begin_.erase(std::unique(row_begin_.begin(), row_begin_.end()), row_begin_.end());
    if (row_begin_.size() < 2 && rows > 0) row_begin_.push_back(rows);
    const std::size_t kept = row_begin_.size() - 1;
    reach_.assign(kept, 0);
    spill_start_.assign(kept + 1, 0);
    std::size_t windows = 0;
    for (std::size_t c = 0; c < kept; ++c) {
      std::size_t reach = row_begin_[c + 1];
      const auto first = partners.begin() + offsets[row_begin_[c]];
      const auto last = partners.begin() + offsets[row_begin_[c + 1]];
      if (first != last) reach = std::max<std::size_t>(reach, *std::max_element(first, last) + 1);
      reach_[c] = reach;
      spill_start_[c + 1] = spill_start_[c] + (reach - row_begin_[c + 1]);
      windows += reach - row_begin_[c];
    }
    const bool fits = kept <= 1 || 2 * windows <= kWindowSlotsPerTwoRows * rows + 8192;
    if (fits && (evened || kept < 4 || kept % 2 == 0)) break;
    if (fits) {
      evened = true;
      wanted = kept - 1;
    } else {
      wanted = std::min(wanted - 1, wanted * 3 / 4);
    }
  }
  const std::size_t chunks = row_begin_.size() - 1;
  first_covering_.assign(chunks, 0);
  covered_end_.assign(chunks, 0);
  std::size_t reached = 0;  // one past the last slot an earlier chunk's window reaches
  for (std::size_t c = 0; c < chunks; ++c) {
    covered_end_[c] = std::clamp(reached, row_begin_[c], row_begin_[c + 1]);
    reached = std::max(reached, reach_[c]);
  }
  // The lowest chunk whose window passes rowBegin(c) never decreases with c.
  std::uint32_t lowest = 0;
  for (std::uint32_t c = 0; c < chunks; ++c) {
    while (reach_[lowest] <= row_begin_[c]) ++lowest;
    first_covering_[c] = lowest;
  }
  force_.resize(spill_start_.back());
  torque_.resize(spill_start_.back());
  if (force_.capacity() > 2 * force_.size() + 4096) {
    force_.shrink_to_fit();
    torque_.shrink_to_fit();
  }
}

ChunkForces PairLoopPartition::start(std::uint32_t chunk, std::span<Vec3> force, std::span<Vec3> torque) {
  const auto begin = static_cast<std::ptrdiff_t>(row_begin_[chunk]);
  const auto end = static_cast<std::ptrdiff_t>(row_begin_[chunk + 1]);
  std::fill(force.begin() + begin, force.begin() + end, Vec3::Zero());
  std::fill(torque.begin() + begin, torque.begin() + end, Vec3::Zero());
  Vec3* spillForce = force_.data() + spill_start_[chunk];
  Vec3* spillTorque = torque_.data() + spill_start_[chunk];
  const std::size_t spill = spill_start_[chunk + 1] - spill_start_[chunk];
  std::fill(spillForce, spillForce + spill, Vec3::Zero());
  std::fill(spillTorque, spillTorque + spill, Vec3::Zero());
  return {force.data(), torque.data(), spillForce, spillTorque, row_begin_[chunk + 1]};
}

void PairLoopPartition::gather(std::uint32_t chunk, std::span<Vec3> force, std::span<Vec3> torque) const {
  // Only the rows an earlier chunk's window reaches (about one cell layer) get a spill;
  // the others' sums are complete already.
  const std::size_t begin = row_begin_[chunk];
  const std::size_t end = covered_end_[chunk];
  const std::uint32_t first = first_covering_[chunk];
  // The sum the old per-chunk windows gave, term for term: 0, the earlier chunks' spills
  // in chunk order, then this chunk's own sum (already in force[s]). Blocks of slots, each
  // earlier chunk's spill added over the block as one run: a loop per slot over the
  // chunks, with a test per chunk, cost more than the additions.
  constexpr std::size_t kBlock = 64;
  Vec3 f[kBlock];
  Vec3 t[kBlock];
  for (std::size_t blockBegin = begin; blockBegin < end; blockBegin += kBlock) {
    const std::size_t blockEnd = std::min(end, blockBegin + kBlock);
    const std::size_t n = blockEnd - blockBegin;
    for (std::size_t k = 0; k < n; ++k) {
      f[k].setZero();
      t[k].setZero();
    }
    for (std::uint32_t c = first; c < chunk; ++c) {
      const std::size_t stop = std::min(blockEnd, reach_[c]);
      if (stop <= blockBegin) continue;
      // Chunk c spills slots from its rowEnd on; blockBegin >= rowBegin(chunk) >= rowEnd(c).
      const std::size_t offset = spill_start_[c] + (blockBegin - row_begin_[c + 1]);
      const Vec3* spillForce = force_.data() + offset;
      const Vec3* spillTorque = torque_.data() + offset;
      for (std::size_t k = 0; k < stop - blockBegin; ++k) {
        f[k] += spillForce[k];
        t[k] += spillTorque[k];
      }
    }
    for (std::size_t k = 0; k < n; ++k) {
      force[blockBegin + k] = f[k] + force[blockBegin + k];
      torque[blockBegin + k] = t[k] + torque[blockBegin + k];
    }
  }
}

std::size_t PairLoopPartition::bytes() const {
  return (force_.capacity() + torque_.capacity()) * sizeof(Vec3) +
         (row_begin_.capacity() + reach_.capacity() + spill_start_.capacity()) * sizeof(std::size_t) +
         first_covering_.capacity() * sizeof(std::uint32_t) + covered_end_.capacity() * sizeof(std::size_t);
}

}  // namespace demlink::core
