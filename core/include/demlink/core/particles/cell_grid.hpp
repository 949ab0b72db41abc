#pragma once
/// Sparse multi-level cell grid (the solver paper's cell-linked list, extended to
/// wide size distributions).
///
/// Levels: particles are sorted into radius classes a factor 2 apart (level k holds
/// radii in [2^k r_min, 2^(k+1) r_min)); each non-empty level bins its particles in
/// cells of edge 2 r_max(level) + skin. A particle of level a finds every partner of
/// a level b >= a in the 27 cells around it in level b's grid (r_i <= r_max(b), so
/// r_i + r_j + skin <= edge of b); pairs of two levels are therefore searched from
/// the smaller particle, and a few large particles no longer make the cells of all
/// the small ones large.
///
/// Sparse cells: a cell is the key of its integer coordinates relative to the
/// particles' median position (of every (n / 4,096)-th particle), particles are
/// sorted by key (a counting sort where the occupied box of cells is dense), and an
/// open-addressing hash finds a cell's particles. Only occupied cells cost memory or time, so a
/// particle far from the rest (no domain bounds) neither grows the cells nor
/// allocates the empty space in between. Coordinates saturate at +-2^20 cells from
/// the median: beyond that, particles share the border cells (slower, still exact,
/// because saturation never moves two particles further apart in cells).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

class CellGrid {
 public:
  /// Levels with radii a factor 2 apart; a scene uses the few its radii need.
  static constexpr int kMaxLevels = 32;

  /// Bins positions by radius class; skin [m] widens every cell.
  void build(std::span<const Vec3> positions, std::span<const double> radii, double skin);

  [[nodiscard]] std::size_t levelCount() const { return levels_.size(); }
  /// Index into the levels (0 = smallest radii) of slot `slot`.
  [[nodiscard]] std::uint32_t levelOfSlot(std::size_t slot) const { return level_of_slot_[slot]; }
  [[nodiscard]] double cellSize(std::size_t level) const { return levels_[level].cell_size; }
  /// Occupied cells of a level.
  [[nodiscard]] std::size_t cellCount(std::size_t level) const { return levels_[level].keys.size(); }

  /// Integer coordinates of a cell of one level.
  using CellCoords = std::array<std::int64_t, 3>;
  /// A cell's key: its coordinates (each in [0, kCoordLimit)), z slowest, x fastest.
  static std::uint64_t pack(std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(z) << (2 * kCoordBits)) | (static_cast<std::uint64_t>(y) << kCoordBits) |
           static_cast<std::uint64_t>(x);
  }
  static std::array<std::int64_t, 3> unpack(std::uint64_t key) {
    const std::uint64_t m = kCoordLimit - 1;
    return {static_cast<std::int64_t>(key & m), static_cast<std::int64_t>((key >> kCoordBits) & m),
            static_cast<std::int64_t>(key >> (2 * kCoordBits))};
  }
  /// The occupied cells of a block of at most 3 x 3 x 3: per row (dz, dy), the indices
  /// [first, last) of its occupied cells (see nearCells()).
  struct NearCells {
    std::array<std::uint32_t, 9> first{};
    std::array<std::uint32_t, 9> last{};
  };

  /// The cell of level `level` holding x.
  [[nodiscard]] CellCoords cellOf(std::size_t level, const Vec3& x) const { return coords(levels_[level], x); }

  /// A block of cells of one level, per axis from lo to hi (at most three cells).
  struct CellBlock {
    CellCoords lo;
    CellCoords hi;
    bool operator==(const CellBlock&) const = default;
  };

  /// The 27 cells around cell c.
  [[nodiscard]] static CellBlock blockAround(const CellCoords& c) {
    return {{c[0] - 1, c[1] - 1, c[2] - 1}, {c[0] + 1, c[1] + 1, c[2] + 1}};
  }

  /// The cells of level `level` that can hold a partner of a smaller particle (radius r,
  /// centre x, of a lower level): those meeting the box x +- (r + r_max(level) + skin),
  /// within the 27 around x's cell. Why not all 27: a small particle's reach into a level
  /// of large cells is little more than half a cell, so the box meets ~2 cells per axis,
  /// ~9.5 of 27 on average in a 1:10 bed (fewer candidates and hash lookups).
  [[nodiscard]] CellBlock partnerBlock(std::size_t level, const Vec3& x, double r) const {
    const Level& l = levels_[level];
    // The margin covers the rounding of x +- reach (the pair test has its own).
    const double reach = r + l.partner_reach + 1e-6 * l.cell_size;
    CellBlock block = blockAround(coords(l, x));
    // A reach that is not finite: the 27 cells, as for a particle of the level itself.
    if (!std::isfinite(reach)) return block;
    const CellCoords lo = coords(l, x - Vec3::Constant(reach));
    const CellCoords hi = coords(l, x + Vec3::Constant(reach));
    for (int d = 0; d < 3; ++d) {
      block.lo[d] = std::max(block.lo[d], lo[d]);
      block.hi[d] = std::min(block.hi[d], hi[d]);
    }
    return block;
  }

  /// The occupied cells of `block` in level `level`. One hash lookup per row (dz, dy),
  /// not one per cell: x is the key's lowest field, so a row's cells are neighbours in
  /// the sorted keys, and the first occupied one leads to the others. Particles of one
  /// cell share the answer (NeighbourList keeps it from one particle to the next).
  [[nodiscard]] NearCells nearCells(std::size_t level, const CellBlock& block) const {
    const Level& l = levels_[level];
    NearCells near;
    std::size_t row = 0;
    for (std::int64_t z = block.lo[2]; z <= block.hi[2]; ++z) {
      for (std::int64_t y = block.lo[1]; y <= block.hi[1]; ++y, ++row) {
        std::uint32_t cell = kNoCell;
        for (std::int64_t x = block.lo[0]; x <= block.hi[0] && cell == kNoCell; ++x) cell = find(l, x, y, z);
        if (cell == kNoCell) continue;
        // find() succeeded, so y and z are in the occupied range; the row's last x is
        // clamped to it so the key cannot carry into y.
        const std::uint64_t lastKey = pack(std::min(block.hi[0], l.highest[0]), y, z);
        std::uint32_t last = cell + 1;
        while (last < l.keys.size() && l.keys[last] <= lastKey) ++last;
        near.first[row] = cell;
        near.last[row] = last;
      }
    }
    return near;
  }
  /// The occupied cells among the 27 around cell c of level `level`.
  [[nodiscard]] NearCells nearCells(std::size_t level, const CellCoords& c) const {
    return nearCells(level, blockAround(c));
  }

  /// Calls visitCell(slots) for every cell of `near` (level `level`), in key order
  /// (z, then y, then x); `slots` are the cell's slots, ascending.
  template <class VisitCell>
  void forEachNearCell(std::size_t level, const NearCells& near, const VisitCell& visitCell) const {
    const Level& l = levels_[level];
    for (std::size_t row = 0; row < near.first.size(); ++row) {
      for (std::uint32_t cell = near.first[row]; cell < near.last[row]; ++cell) {
        visitCell(std::span<const std::uint32_t>(l.slots.data() + l.start[cell], l.start[cell + 1] - l.start[cell]));
      }
    }
  }

  /// Calls visit(j) for every slot j of level `level` in the 27 cells around x.
  template <class Visit>
  void forEachNear(std::size_t level, const Vec3& x, const Visit& visit) const {
    forEachNearCell(level, nearCells(level, cellOf(level, x)), [&](std::span<const std::uint32_t> slots) {
      for (const std::uint32_t j : slots) visit(j);
    });
  }

  /// Calls visit(j) for every slot j, of every level, whose cell meets the box [lo, hi]
  /// (a superset of the particles with centres in it). Costs at most the smaller of the
  /// box's cells and the occupied cells.
  template <class Visit>
  void forEachInBox(const Vec3& lo, const Vec3& hi, const Visit& visit) const {
    for (const Level& l : levels_) {
      auto a = coords(l, lo);
      auto b = coords(l, hi);
      double boxCells = 1.0;
      for (int d = 0; d < 3; ++d) {
        a[d] = std::max(a[d], l.lowest[d]);
        b[d] = std::min(b[d], l.highest[d]);
        if (a[d] > b[d]) boxCells = 0.0;
        boxCells *= static_cast<double>(b[d] - a[d] + 1);
      }
      if (boxCells <= 0.0) continue;
      const auto visitCell = [&](std::uint32_t cell) {
        for (std::uint32_t k = l.start[cell]; k < l.start[cell + 1]; ++k) visit(l.slots[k]);
      };
      if (boxCells > static_cast<double>(l.keys.size())) {
        for (std::uint32_t cell = 0; cell < l.keys.size(); ++cell) {
          const auto k = unpack(l.keys[cell]);
          if (k[0] >= a[0] && k[0] <= b[0] && k[1] >= a[1] && k[1] <= b[1] && k[2] >= a[2] && k[2] <= b[2]) {
            visitCell(cell);
          }
        }
        continue;
      }
      for (std::int64_t z = a[2]; z <= b[2]; ++z) {
        for (std::int64_t y = a[1]; y <= b[1]; ++y) {
          for (std::int64_t x = a[0]; x <= b[0]; ++x) {
            const std::uint32_t cell = find(l, x, y, z);
            if (cell != kNoCell) visitCell(cell);
          }
        }
      }
    }
  }

  /// Slots ordered by cells of the largest level: a locality-friendly permutation of the
  /// particles that keeps neighbours close in slot order. The slowest-varying axis is the
  /// one whose fullest layer of cells holds the fewest particles, then the same rule for
  /// the other two (ties keep z, then y, slowest). Why: the threaded pair loop cuts the
  /// slots into chunks no thinner than one layer of the slowest axis
  /// (PairLoopPartition), so that axis should have many layers of even work. A settling
  /// bed in a wide box ordered z first put the dense, contact-rich bottom in one or two
  /// chunks and free flight in the rest; ordered by x, every chunk holds a full column
  /// (5,000-sphere deposition, 20,000 steps: 2.59 -> 2.45 s on two threads, 4.07 ->
  /// 4.00 s on one; docs/benchmarks.md).
  [[nodiscard]] std::vector<std::uint32_t> spatialOrder(std::span<const Vec3> positions) const;

  /// Bytes held (capacity of every array).
  [[nodiscard]] std::size_t bytes() const;

 private:
  static constexpr std::uint32_t kNoCell = 0xFFFFFFFFu;
  static constexpr std::int64_t kCoordBits = 21;
  static constexpr std::int64_t kCoordLimit = std::int64_t{1} << kCoordBits;  ///< coordinates in [0, limit)

  struct Level {
    double cell_size = 1.0;  ///< [m]
    double inv_cell_size = 1.0;
    double partner_reach = 0.0;  ///< r_max + skin: a partner j lies within r_i + this of i [m]
    std::vector<std::uint64_t> keys;     ///< occupied cells, ascending
    std::vector<std::uint32_t> start;    ///< cell c holds slots[start[c] .. start[c+1])
    std::vector<std::uint32_t> slots;    ///< this level's slots by cell, then slot
    std::vector<std::uint32_t> table;    ///< open addressing: cell index or kNoCell
    std::uint64_t mask = 0;
    std::array<std::int64_t, 3> lowest{0, 0, 0};   ///< occupied coordinate range
    std::array<std::int64_t, 3> highest{-1, -1, -1};
    /// One bit per cell of the occupied range (x fastest), when that range holds at most
    /// kOccupancyBitsPerCell cells per occupied one; empty otherwise.
    std::vector<std::uint64_t> occupied;
    std::array<std::int64_t, 3> extent{0, 0, 0};  ///< cells per axis of the occupied range
  };

  /// Why a bitmap beside the hash: most cells a search visits are empty (a loose bed, a
  /// level of few large particles), and a bit answers "empty" in one load where the hash
  /// probes; capped so a far outlier's range costs no more than 8 bytes per occupied cell.
  static constexpr std::uint64_t kOccupancyBitsPerCell = 64;

  [[nodiscard]] std::array<std::int64_t, 3> coords(const Level& l, const Vec3& x) const;
  /// Every bit of the key reaches the low bits the table uses (MurmurHash3's 64-bit
  /// finaliser). A multiply alone moves information only upwards: its bits 17 and up, the
  /// old hash, never saw z, so all cells of one (x, y) column shared a probe chain, and a
  /// 1.4 m column of spheres probed ~100 slots per cell looked up.
  static std::uint64_t hash(std::uint64_t key) {
    key ^= key >> 33;
    key *= 0xFF51AFD7ED558CCDull;
    key ^= key >> 33;
    key *= 0xC4CEB9FE1A85EC53ull;
    return key ^ (key >> 33);
  }
  static std::uint32_t find(const Level& l, std::int64_t x, std::int64_t y, std::int64_t z) {
    if (x < l.lowest[0] || x > l.highest[0] || y < l.lowest[1] || y > l.highest[1] || z < l.lowest[2] ||
        z > l.highest[2]) {
      return kNoCell;
    }
    if (!l.occupied.empty()) {
      const std::uint64_t bit = occupancyBit(l, {x, y, z});
      if (((l.occupied[bit >> 6] >> (bit & 63)) & 1u) == 0) return kNoCell;
    }
    const std::uint64_t key = pack(x, y, z);
    for (std::uint64_t h = hash(key) & l.mask;; h = (h + 1) & l.mask) {
      const std::uint32_t cell = l.table[h];
      if (cell == kNoCell || l.keys[cell] == key) return cell;
    }
  }
  /// Bit of cell c (inside the occupied range) in Level::occupied.
  static std::uint64_t occupancyBit(const Level& l, const std::array<std::int64_t, 3>& c) {
    return static_cast<std::uint64_t>(((c[2] - l.lowest[2]) * l.extent[1] + (c[1] - l.lowest[1])) * l.extent[0] +
                                      (c[0] - l.lowest[0]));
  }
  static void buildOccupancy(Level& l);
  void buildLevel(Level& l, std::span<const Vec3> positions, std::span<const std::uint32_t> members);

  Vec3 origin_ = Vec3::Zero();
  std::vector<Level> levels_;
  std::vector<std::uint8_t> level_of_slot_;
};

}  // namespace demlink::core
