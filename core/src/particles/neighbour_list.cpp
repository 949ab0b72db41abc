#include "demlink/core/particles/neighbour_list.hpp"

#include <algorithm>
#include <array>
#include <utility>

#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/parallel/parallel_loops.hpp"

namespace demlink::core {

bool NeighbourList::needsRebuild(std::span<const Vec3> positions, ThreadPool* pool) const {
  if (positions.size() != position_at_build_.size()) return true;
  const double limit2 = 0.25 * skin_ * skin_;
  const std::size_t n = positions.size();
  const std::uint32_t chunks = chunkCount(n);
  std::vector<char> moved(chunks, 0);
  parallelParts(pool, chunks, [&](std::uint32_t chunk) {
    for (std::size_t i = chunkBegin(n, chunks, chunk); i < chunkBegin(n, chunks, chunk + 1); ++i) {
      if ((positions[i] - position_at_build_[i]).squaredNorm() > limit2) {
        moved[chunk] = 1;
        return;
      }
    }
  });
  return std::find(moved.begin(), moved.end(), 1) != moved.end();
}

namespace {

/// A pair found from its higher slot: it belongs to row `row` (< partner).
struct ForeignPair {
  std::uint32_t row;
  std::uint32_t partner;
  bool operator<(const ForeignPair& other) const {
    return row != other.row ? row < other.row : partner < other.partner;
  }
};

/// Searches the pairs of rows [begin, end): particle i looks in its own level for
/// partners j > i and in every larger level for all partners (pairs of two levels
/// are found from the smaller particle only, see CellGrid). Partners j > i go to
/// `out` (row by row, ascending; counts[i] per row), the others to `foreign`.
/// kClumps: skip partners of the same clump.
///
/// Slots are kept in cell order (World sorts them), so consecutive rows mostly share
/// a cell and its 27 neighbours, which are looked up once for them; and a cell's slots
/// are ascending, so in the own level the partners j <= i of a cell are skipped
/// without reading their positions.
template <bool kClumps>
void findPartners(const CellGrid& grid, std::span<const Vec3> x, std::span<const double> r,
                  std::span<const std::uint64_t> clump, double skin, std::size_t begin, std::size_t end,
                  std::vector<std::uint32_t>& out, std::vector<std::uint32_t>& counts,
                  std::vector<ForeignPair>& foreign) {
  struct Cached {
    bool valid = false;
    CellGrid::CellBlock block{};
    CellGrid::NearCells near;
  };
  std::array<Cached, CellGrid::kMaxLevels> cached{};
  // out[0, used) holds the partners found; out itself is only grown (doubling) so
  // candidates can be written before they are tested.
  std::size_t used = out.size();
  auto room = [&](std::size_t more) {
    if (out.size() < used + more) out.resize(std::max(2 * out.size(), used + more));
  };
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t rowStart = used;
    const std::uint32_t own = grid.levelOfSlot(i);
    const auto self = static_cast<std::uint32_t>(i);
    const Vec3 xi = x[i];
    const double ri = r[i];
    auto consider = [&](std::uint32_t j) {
      if constexpr (kClumps) {
        if (clump[i] != 0 && clump[i] == clump[j]) return;
      }
      const double cutoff = ri + r[j] + skin;
      if ((x[j] - xi).squaredNorm() >= cutoff * cutoff) return;
      if (j > self) {
        room(1);
        out[used++] = j;
      } else {
        foreign.push_back({j, self});
      }
    };
    for (std::size_t level = own; level < grid.levelCount(); ++level) {
      Cached& c = cached[level];
      const CellGrid::CellBlock block = level == own ? CellGrid::blockAround(grid.cellOf(level, xi))
                                                     : grid.partnerBlock(level, xi, ri);
      if (!c.valid || block != c.block) c = {true, block, grid.nearCells(level, block)};
      if (level != own) {
        grid.forEachNearCell(level, c.near, [&](std::span<const std::uint32_t> slots) {
          for (const std::uint32_t j : slots) consider(j);
        });
        continue;
      }
      grid.forEachNearCell(level, c.near, [&](std::span<const std::uint32_t> slots) {
        if (slots.back() <= self) return;
        // A cell's slots are ascending and few: a forward scan finds the first j > i in
        // one or two steps (cells after i's own hold only such slots).
        auto k = slots.begin();
        while (*k <= self) ++k;
        if constexpr (kClumps) {
          for (; k != slots.end(); ++k) consider(*k);
        } else {
          // Every candidate is written and the end moves past the partners only: no
          // branch on a test that fails for most candidates in no learnable pattern.
          room(static_cast<std::size_t>(slots.end() - k));
          std::uint32_t* w = out.data() + used;
          for (; k != slots.end(); ++k) {
            const std::uint32_t j = *k;
            const double cutoff = ri + r[j] + skin;
            *w = j;
            w += static_cast<std::size_t>((x[j] - xi).squaredNorm() < cutoff * cutoff);
          }
          used = static_cast<std::size_t>(w - out.data());
        }
      });
    }
    // Ascending partners: deterministic order independent of cell traversal.
    std::sort(out.begin() + static_cast<std::ptrdiff_t>(rowStart), out.begin() + static_cast<std::ptrdiff_t>(used));
    counts[i] = static_cast<std::uint32_t>(used - rowStart);
  }
  out.resize(used);
}

/// A spring of the previous list at its pair's current slots (a < b): its tangential
/// history, sign-flipped when reordering swapped the pair's ends.
struct CarriedSpring {
  std::uint32_t a;
  std::uint32_t b;
  Vec3 history;
};

}  // namespace

void NeighbourList::build(const ParticleArrays& particles, std::span<const std::uint32_t> newSlotOfOld,
                          ThreadPool* pool, bool excludeSameClump) {
  const std::size_t n = particles.size();
  const std::span<const Vec3> x = particles.position;
  const std::span<const double> r = particles.radius;

  // The previous list's springs (pairs with a non-zero history), at their current slots.
  // Only they are kept while the new list is built in the old one's arrays: their memory
  // is reused, warm, rather than allocated and faulted in again at every build, and a
  // build holds ~32 bytes per touching pair beside the list instead of a second list.
  const std::size_t oldCount = rowCount();
  const std::uint32_t oldChunks = chunkCount(oldCount);
  std::vector<std::vector<CarriedSpring>> carried(oldChunks);
  parallelParts(pool, oldChunks, [&](std::uint32_t part) {
    for (std::size_t oi = chunkBegin(oldCount, oldChunks, part); oi < chunkBegin(oldCount, oldChunks, part + 1); ++oi) {
      const std::uint32_t a0 = newSlotOfOld.empty() ? static_cast<std::uint32_t>(oi) : newSlotOfOld[oi];
      if (a0 == kRemovedSlot) continue;
      for (std::uint32_t k = offsets_[oi]; k < offsets_[oi + 1]; ++k) {
        if (history_[k].isZero(0.0)) continue;
        const std::uint32_t b0 = newSlotOfOld.empty() ? partners_[k] : newSlotOfOld[partners_[k]];
        if (b0 == kRemovedSlot) continue;
        // Ownership may flip when slots are reordered; the spring of B relative to A
        // then changes sign.
        const bool flipped = b0 < a0;
        carried[part].push_back({flipped ? b0 : a0, flipped ? a0 : b0, flipped ? Vec3(-history_[k]) : history_[k]});
      }
    }
  });

  grid_.build(x, r, skin_);
  // Rows are independent: each chunk finds its rows' partners into its own
  // buffer; the buffers are then laid end to end in chunk order.
  // Rows per chunk: a row's search costs ~27 cells, far more than a kick.
  const std::uint32_t parts = chunkCount(n, 512);
  std::vector<std::vector<std::uint32_t>> found(parts);
  std::vector<std::vector<ForeignPair>> foreignOf(parts);
  std::vector<std::uint32_t> counts(n);
  const std::size_t expectedPairs = partners_.size();
  parallelParts(pool, parts, [&](std::uint32_t part) {
    found[part].reserve(expectedPairs / parts + 16);
    const std::size_t begin = chunkBegin(n, parts, part);
    const std::size_t end = chunkBegin(n, parts, part + 1);
    if (excludeSameClump) {
      findPartners<true>(grid_, x, r, particles.clump_id, skin_, begin, end, found[part], counts, foreignOf[part]);
    } else {
      findPartners<false>(grid_, x, r, particles.clump_id, skin_, begin, end, found[part], counts, foreignOf[part]);
    }
  });
  // Pairs found from their higher slot (a smaller particle before a larger one),
  // sorted by row: foreignStart[i] .. foreignStart[i+1] are row i's.
  std::vector<ForeignPair> foreign;
  for (const auto& list : foreignOf) foreign.insert(foreign.end(), list.begin(), list.end());
  std::sort(foreign.begin(), foreign.end());
  std::vector<std::uint32_t> foreignStart(n + 1, 0);
  for (const ForeignPair& pair : foreign) ++foreignStart[pair.row + 1];
  for (std::size_t i = 0; i < n; ++i) foreignStart[i + 1] += foreignStart[i];
  offsets_.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    offsets_[i + 1] = offsets_[i] + counts[i] + (foreignStart[i + 1] - foreignStart[i]);
  }
  const std::size_t pairs = offsets_[n];
  partners_.resize(pairs);
  rows_.resize(pairs);
  history_.resize(pairs);
  sprung_.resize(pairs);
  reduced_.resize(pairs);
  parallelParts(pool, parts, [&](std::uint32_t part) {
    const std::size_t begin = chunkBegin(n, parts, part);
    const std::size_t end = chunkBegin(n, parts, part + 1);
    auto own = found[part].begin();
    for (std::size_t i = begin; i < end; ++i) {
      // The row's own partners and its foreign ones, both ascending, merged.
      auto out = partners_.begin() + offsets_[i];
      out = std::copy(own, own + counts[i], out);
      own += counts[i];
      for (std::uint32_t f = foreignStart[i]; f < foreignStart[i + 1]; ++f) *out++ = foreign[f].partner;
      std::inplace_merge(partners_.begin() + offsets_[i], partners_.begin() + offsets_[i] + counts[i], out);
    }
    const auto first = static_cast<std::ptrdiff_t>(offsets_[begin]);
    const auto last = static_cast<std::ptrdiff_t>(offsets_[end]);
    std::fill(history_.begin() + first, history_.begin() + last, Vec3::Zero());
    std::fill(sprung_.begin() + first, sprung_.begin() + last, std::uint8_t{0});
    for (std::size_t i = begin; i < end; ++i) {
      for (std::uint32_t k = offsets_[i]; k < offsets_[i + 1]; ++k) {
        const std::uint32_t j = partners_[k];
        rows_[k] = static_cast<std::uint32_t>(i);
        reduced_[k] = {r[i] * r[j] / (r[i] + r[j]), 1.0 / (particles.inv_mass[i] + particles.inv_mass[j])};
      }
    }
  });

  // The springs back into the pairs that are still listed. Each new pair has at most one
  // old pair, so parts write disjoint entries.
  parallelParts(pool, oldChunks, [&](std::uint32_t part) {
    for (const CarriedSpring& spring : carried[part]) {
      const auto rowBegin = partners_.begin() + offsets_[spring.a];
      const auto rowEnd = partners_.begin() + offsets_[spring.a + 1];
      const auto it = std::lower_bound(rowBegin, rowEnd, spring.b);
      if (it != rowEnd && *it == spring.b) {
        const auto pair = static_cast<std::size_t>(it - partners_.begin());
        history_[pair] = spring.history;
        sprung_[pair] = 1;
      }
    }
  });
  position_at_build_.assign(x.begin(), x.end());
  ++builds_;
}

std::size_t NeighbourList::bytes() const {
  return grid_.bytes() + sprung_.capacity() +
         (offsets_.capacity() + partners_.capacity() + rows_.capacity()) * sizeof(std::uint32_t) +
         (history_.capacity() + position_at_build_.capacity()) * sizeof(Vec3) +
         reduced_.capacity() * sizeof(ReducedPair);
}

template <>
struct StateCodec<ReducedPair> {
  static constexpr std::size_t kBytes = 2 * sizeof(double);
  static void write(StateWriter& out, const ReducedPair& value) {
    out.write(value.radius);
    out.write(value.mass);
  }
  static void read(StateReader& in, ReducedPair& value) {
    value.radius = in.read<double>();
    value.mass = in.read<double>();
  }
};

void NeighbourList::save(StateWriter& out) const {
  out.write(skin_);
  out.write(builds_);
  out.writeVector(offsets_);
  out.writeVector(partners_);
  out.writeVector(history_);
  out.writeVector(reduced_);
  out.writeVector(position_at_build_);
}

void NeighbourList::restore(StateReader& in) {
  NeighbourList staged(in.read<double>());
  requireEqual(in, "neighbour skin", staged.skin_, skin_);
  staged.builds_ = in.read<std::uint64_t>();
  staged.offsets_ = in.readVector<std::uint32_t>();
  staged.partners_ = in.readVector<std::uint32_t>();
  staged.history_ = in.readVector<Vec3>();
  staged.reduced_ = in.readVector<ReducedPair>();
  staged.position_at_build_ = in.readVector<Vec3>();
  in.requireEnd();
  requireOffsets(in, staged.offsets_, staged.partners_.size(), "neighbour offsets");
  requireIndices(in, staged.partners_, staged.rowCount(), "neighbour partner");
  requireSameLength(in, staged.history_, staged.partners_, "histories and partners differ in length");
  requireSameLength(in, staged.reduced_, staged.partners_, "pair data and partners differ in length");
  staged.rows_.resize(staged.partners_.size());
  for (std::size_t i = 0; i < staged.rowCount(); ++i) {
    std::fill(staged.rows_.begin() + staged.offsets_[i], staged.rows_.begin() + staged.offsets_[i + 1],
              static_cast<std::uint32_t>(i));
  }
  staged.sprung_.resize(staged.history_.size());
  for (std::size_t k = 0; k < staged.history_.size(); ++k) staged.sprung_[k] = staged.history_[k].isZero(0.0) ? 0 : 1;
  *this = std::move(staged);
}

}  // namespace demlink::core
