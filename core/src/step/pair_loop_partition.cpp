#include "demlink/core/step/pair_loop_partition.hpp"

#include <algorithm>

namespace demlink::core {
namespace {

constexpr std::size_t kMaxChunksPlanned = 4096;

}  // namespace

void PairLoopPartition::cut(std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> partners,
                            std::size_t wanted) {
  const std::size_t rows = offsets.empty() ? 0 : offsets.size() - 1;
  const std::uint64_t pairs = offsets.empty() ? 0 : offsets.back();
  row_begin_.assign(1, 0);
  reach_.clear();
  // Chunk c ends at the first row whose pairs from the chunk's first row reach an equal
  // share of the pairs left for the chunks left (rows with no pairs go to the chunk
  // before): a chunk the reach stretched leaves fewer pairs to the rest, and they share
  // them evenly, not the last one or two alone.
  const auto rowOfShare = [&](std::size_t begin, std::size_t c) -> std::size_t {
    if (c + 1 >= wanted) return rows;
    const std::uint64_t target = offsets[begin] + (pairs - offsets[begin]) / (wanted - c);
    return static_cast<std::size_t>(
        std::lower_bound(offsets.begin(), offsets.begin() + static_cast<std::ptrdiff_t>(rows), target) -
        offsets.begin());
  };
  std::size_t mustEnd = 0;  // the previous chunk's reach: this chunk's rows end no earlier
  for (std::size_t c = 0; row_begin_.back() < rows; ++c) {
    const std::size_t begin = row_begin_.back();
    const std::size_t end = std::min(rows, std::max({rowOfShare(begin, c), begin + 1, mustEnd}));
    std::size_t reach = end;
    const auto first = partners.begin() + offsets[begin];
    const auto last = partners.begin() + offsets[end];
    if (first != last) reach = std::max<std::size_t>(reach, *std::max_element(first, last) + 1);
    row_begin_.push_back(end);
    reach_.push_back(reach);
    mustEnd = reach;
  }
}

void PairLoopPartition::plan(std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> partners) {
  const std::size_t rows = offsets.empty() ? 0 : offsets.size() - 1;
  const std::uint64_t pairs = offsets.empty() ? 0 : offsets.back();
  // About kPairsPerChunk pairs per chunk, but at least 16 chunks of >= 64 rows, so a
  // small scene still has chunks to share.
  std::size_t wanted = std::max<std::size_t>(static_cast<std::size_t>(pairs / kPairsPerChunk),
                                             std::min<std::size_t>(16, rows / 64));
  wanted = std::clamp<std::size_t>(wanted, 1, kMaxChunksPlanned);
  // Chunks stretched by the reach come out fewer than wanted; cut again for that many, so
  // they hold about equal pairs again. From 4 on, a multiple of 4: the even chunks then have an
  // even count, and two threads' home ranges hold as many chunks each (a thread that has
  // claimed its last chunk leaves nothing to steal). The count falls at every retry.
  for (;;) {
    cut(offsets, partners, wanted);
    const std::size_t got = chunks();
    const auto lastPairs = [&] { return pairs - offsets[rowBegin(static_cast<std::uint32_t>(got - 1))]; };
    if (got < wanted) {
      wanted = got;
    } else if (got >= 4 && got % 4 != 0) {
      wanted = got - got % 4;
    } else if (got > 1 && 2 * lastPairs() * got < pairs) {
      // The reach stretched every chunk and the last ones got the remainder: fewer chunks.
      wanted = got - 1;
    } else {
      break;
    }
  }
}

void PairLoopPartition::resetWaits() {
  const std::uint32_t n = chunks();
  waits_.resize(n);
  for (std::uint32_t odd = 1; odd < n; odd += 2) waits_[odd] = odd + 1 < n ? 2 : 1;
}

ChunkForces PairLoopPartition::start(std::uint32_t chunk, std::span<Vec3> force, std::span<Vec3> torque,
                                     bool clear) const {
  if (clear && chunk % 2 == 0) {
    const auto begin = static_cast<std::ptrdiff_t>(row_begin_[chunk]);
    const auto end = static_cast<std::ptrdiff_t>(row_begin_[std::min<std::size_t>(chunk + 2, row_begin_.size() - 1)]);
    std::fill(force.begin() + begin, force.begin() + end, Vec3::Zero());
    std::fill(torque.begin() + begin, torque.begin() + end, Vec3::Zero());
  }
  return {force.data(), torque.data()};
}

std::size_t PairLoopPartition::bytes() const {
  return (row_begin_.capacity() + reach_.capacity()) * sizeof(std::size_t) + waits_.capacity() * sizeof(std::uint32_t);
}

}  // namespace demlink::core
