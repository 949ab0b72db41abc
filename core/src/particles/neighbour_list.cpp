#include "demlink/core/particles/neighbour_list.hpp"

#include <algorithm>
#include <utility>

#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/step/parallel.hpp"

namespace demlink::core {

bool NeighbourList::needsRebuild(std::span<const Vec3> positions, ThreadPool* pool) const {
  if (positions.size() != position_at_build_.size()) return true;
  const double limit2 = 0.25 * skin_ * skin_;
  const std::uint32_t parts = pool != nullptr ? pool->size() : 1;
  std::vector<char> moved(parts, 0);
  parallelParts(pool, parts, [&](std::uint32_t part) {
    const std::size_t begin = positions.size() * part / parts;
    const std::size_t end = positions.size() * (part + 1) / parts;
    for (std::size_t i = begin; i < end; ++i) {
      if ((positions[i] - position_at_build_[i]).squaredNorm() > limit2) {
        moved[part] = 1;
        return;
      }
    }
  });
  return std::find(moved.begin(), moved.end(), 1) != moved.end();
}

namespace {

/// Appends to `out` the partners j > i of rows [begin, end) and writes each
/// row's partner count to counts[i]. kClumps: skip partners of the same clump.
template <bool kClumps>
void findPartners(const CellGrid& grid, std::span<const Vec3> x, std::span<const double> r,
                  std::span<const std::uint64_t> clump, double skin, std::size_t begin, std::size_t end,
                  std::vector<std::uint32_t>& out, std::vector<std::uint32_t>& counts) {
  const auto& dims = grid.dims();
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t rowStart = out.size();
    const auto c = grid.cellCoords(x[i]);
    for (std::int64_t dz = -1; dz <= 1; ++dz) {
      const std::int64_t iz = c[2] + dz;
      if (iz < 0 || iz >= dims[2]) continue;
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const std::int64_t iy = c[1] + dy;
        if (iy < 0 || iy >= dims[1]) continue;
        for (std::int64_t dx = -1; dx <= 1; ++dx) {
          const std::int64_t ix = c[0] + dx;
          if (ix < 0 || ix >= dims[0]) continue;
          for (const std::uint32_t j : grid.cell(grid.cellIndex(ix, iy, iz))) {
            if (j <= i) continue;
            if constexpr (kClumps) {
              if (clump[i] != 0 && clump[i] == clump[j]) continue;
            }
            const double cutoff = r[i] + r[j] + skin;
            if ((x[j] - x[i]).squaredNorm() < cutoff * cutoff) out.push_back(j);
          }
        }
      }
    }
    // Ascending partners: deterministic order independent of cell traversal.
    std::sort(out.begin() + static_cast<std::ptrdiff_t>(rowStart), out.end());
    counts[i] = static_cast<std::uint32_t>(out.size() - rowStart);
  }
}

}  // namespace

void NeighbourList::build(const ParticleArrays& particles, std::span<const std::uint32_t> newSlotOfOld,
                          ThreadPool* pool, bool excludeSameClump) {
  const std::size_t n = particles.size();
  const std::span<const Vec3> x = particles.position;
  const std::span<const double> r = particles.radius;
  const double maxRadius = n > 0 ? *std::max_element(r.begin(), r.end()) : 0.0;
  grid_.build(x, 2.0 * maxRadius + skin_);

  std::vector<std::uint32_t> oldOffsets;
  std::vector<std::uint32_t> oldPartners;
  std::vector<Vec3> oldHistory;
  oldOffsets.swap(offsets_);
  oldPartners.swap(partners_);
  oldHistory.swap(history_);

  // Rows are independent: each part finds its rows' partners into its own
  // buffer; the buffers are then laid end to end in part order.
  const std::uint32_t parts = pool != nullptr ? pool->size() : 1;
  std::vector<std::vector<std::uint32_t>> found(parts);
  std::vector<std::uint32_t> counts(n);
  parallelParts(pool, parts, [&](std::uint32_t part) {
    found[part].reserve(oldPartners.size() / parts + 16);
    const std::size_t begin = n * part / parts;
    const std::size_t end = n * (part + 1) / parts;
    if (excludeSameClump) {
      findPartners<true>(grid_, x, r, particles.clump_id, skin_, begin, end, found[part], counts);
    } else {
      findPartners<false>(grid_, x, r, particles.clump_id, skin_, begin, end, found[part], counts);
    }
  });
  offsets_.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) offsets_[i + 1] = offsets_[i] + counts[i];
  partners_.resize(offsets_[n]);
  history_.assign(partners_.size(), Vec3::Zero());
  reduced_.resize(partners_.size());
  parallelParts(pool, parts, [&](std::uint32_t part) {
    const std::size_t begin = n * part / parts;
    const std::size_t end = n * (part + 1) / parts;
    std::copy(found[part].begin(), found[part].end(), partners_.begin() + offsets_[begin]);
    for (std::size_t i = begin; i < end; ++i) {
      for (std::uint32_t k = offsets_[i]; k < offsets_[i + 1]; ++k) {
        const std::uint32_t j = partners_[k];
        reduced_[k] = {r[i] * r[j] / (r[i] + r[j]), 1.0 / (particles.inv_mass[i] + particles.inv_mass[j])};
      }
    }
  });

  // Carry the history of pairs that were touching (non-zero spring) over. Each
  // new pair has at most one old pair, so parts write disjoint entries.
  const std::size_t oldCount = oldOffsets.empty() ? 0 : oldOffsets.size() - 1;
  parallelParts(pool, parts, [&](std::uint32_t part) {
    for (std::size_t oi = oldCount * part / parts; oi < oldCount * (part + 1) / parts; ++oi) {
      const std::uint32_t a0 = newSlotOfOld.empty() ? static_cast<std::uint32_t>(oi) : newSlotOfOld[oi];
      if (a0 == kRemovedSlot) continue;
      for (std::uint32_t k = oldOffsets[oi]; k < oldOffsets[oi + 1]; ++k) {
        if (oldHistory[k].isZero(0.0)) continue;
        const std::uint32_t b0 = newSlotOfOld.empty() ? oldPartners[k] : newSlotOfOld[oldPartners[k]];
        if (b0 == kRemovedSlot) continue;
        // Ownership may flip when slots are reordered; the spring of B relative
        // to A then changes sign.
        const bool flipped = b0 < a0;
        const std::uint32_t a = flipped ? b0 : a0;
        const std::uint32_t b = flipped ? a0 : b0;
        const auto rowBegin = partners_.begin() + offsets_[a];
        const auto rowEnd = partners_.begin() + offsets_[a + 1];
        const auto it = std::lower_bound(rowBegin, rowEnd, b);
        if (it != rowEnd && *it == b) {
          history_[static_cast<std::size_t>(it - partners_.begin())] = flipped ? Vec3(-oldHistory[k]) : oldHistory[k];
        }
      }
    }
  });
  position_at_build_.assign(x.begin(), x.end());
  ++builds_;
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
  *this = std::move(staged);
}

}  // namespace demlink::core
