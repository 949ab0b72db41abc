#include "demlink/core/particles/cell_grid.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>

namespace demlink::core {
namespace {

/// Median of one coordinate over every (n / kMedianSample)-th position, 4,096 to 8,191
/// of them once n >= 4,096 (robust to a few far particles, unlike the bounding box). Why
/// a sample: the origin only places the cell boundaries; the lists found are exact for
/// any origin, and the full median was a fifth of the grid's build at 50,000 particles.
double medianOf(std::span<const Vec3> positions, int axis) {
  constexpr std::size_t kMedianSample = 4096;
  const std::size_t stride = std::max<std::size_t>(1, positions.size() / kMedianSample);
  std::vector<double> values;
  values.reserve(positions.size() / stride + 1);
  for (std::size_t i = 0; i < positions.size(); i += stride) {
    const double x = positions[i][axis];
    if (std::isfinite(x)) values.push_back(x);
  }
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

/// Most particles in one layer [-], `layerOf(i)` the layer of particle i of n: a
/// histogram over the occupied range, or a sort when far outliers make the range longer
/// than the particle count.
template <class LayerOf>
std::size_t fullestLayer(std::size_t n, const LayerOf& layerOf) {
  if (n == 0) return 0;
  std::int64_t low = layerOf(0);
  std::int64_t high = low;
  for (std::size_t i = 1; i < n; ++i) {
    const std::int64_t layer = layerOf(i);
    low = std::min(low, layer);
    high = std::max(high, layer);
  }
  std::size_t fullest = 0;
  const auto range = static_cast<std::uint64_t>(high - low) + 1;
  if (range <= n + 64) {
    std::vector<std::uint32_t> count(range, 0);
    for (std::size_t i = 0; i < n; ++i) {
      fullest = std::max<std::size_t>(fullest, ++count[static_cast<std::size_t>(layerOf(i) - low)]);
    }
    return fullest;
  }
  std::vector<std::int64_t> sorted(n);
  for (std::size_t i = 0; i < n; ++i) sorted[i] = layerOf(i);
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 0; k < n;) {
    const std::size_t first = k;
    while (k < n && sorted[k] == sorted[first]) ++k;
    fullest = std::max(fullest, k - first);
  }
  return fullest;
}

struct KeyedSlot {
  std::uint64_t key;
  std::uint32_t slot;
  bool operator<(const KeyedSlot& other) const {
    return key != other.key ? key < other.key : slot < other.slot;
  }
};

/// Sorts `keyed` (given in ascending slot order; keys from CellGrid::pack) by key, then
/// slot. Where the box of the keys' cells holds at most kDenseCellsPerSlot cells per slot
/// (a bed, a column), a stable counting sort over that box: linear, and ~5x faster than
/// the comparison sort at 50,000 particles; otherwise (far outliers) the comparison sort.
/// Both give the same order.
void sortByCell(std::vector<KeyedSlot>& keyed) {
  constexpr std::uint64_t kDenseCellsPerSlot = 4;
  if (keyed.size() < 2) return;
  std::array<std::int64_t, 3> lo = CellGrid::unpack(keyed.front().key);
  std::array<std::int64_t, 3> hi = lo;
  for (const KeyedSlot& k : keyed) {
    const auto c = CellGrid::unpack(k.key);
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], c[d]);
      hi[d] = std::max(hi[d], c[d]);
    }
  }
  const std::uint64_t limit = kDenseCellsPerSlot * keyed.size() + 64;
  std::array<std::uint64_t, 3> extent{};
  std::uint64_t cells = 1;
  for (int d = 0; d < 3; ++d) {
    extent[d] = static_cast<std::uint64_t>(hi[d] - lo[d]) + 1;
    cells *= extent[d];
    if (cells > limit) {  // checked per axis: no overflow
      std::sort(keyed.begin(), keyed.end());
      return;
    }
  }
  // The dense index grows with the key (z slowest, x fastest, as pack()).
  const auto denseIndex = [&](std::uint64_t key) {
    const auto c = CellGrid::unpack(key);
    return (static_cast<std::uint64_t>(c[2] - lo[2]) * extent[1] + static_cast<std::uint64_t>(c[1] - lo[1])) *
               extent[0] +
           static_cast<std::uint64_t>(c[0] - lo[0]);
  };
  std::vector<std::uint32_t> start(cells + 1, 0);
  for (const KeyedSlot& k : keyed) ++start[denseIndex(k.key) + 1];
  for (std::uint64_t c = 0; c < cells; ++c) start[c + 1] += start[c];
  std::vector<KeyedSlot> sorted(keyed.size());
  for (const KeyedSlot& k : keyed) sorted[start[denseIndex(k.key)]++] = k;
  keyed.swap(sorted);
}

}  // namespace

std::array<std::int64_t, 3> CellGrid::coords(const Level& l, const Vec3& x) const {
  constexpr double kHalf = static_cast<double>(kCoordLimit / 2);
  std::array<std::int64_t, 3> c{};
  for (int d = 0; d < 3; ++d) {
    // Saturated in double before the conversion (an out-of-range double -> int64 is UB;
    // NaN lands in the lowest cell).
    const double k = std::floor((x[d] - origin_[d]) * l.inv_cell_size);
    c[d] = !(k > -kHalf) ? 0 : (k >= kHalf - 1.0 ? kCoordLimit - 1 : static_cast<std::int64_t>(k + kHalf));
  }
  return c;
}

void CellGrid::build(std::span<const Vec3> positions, std::span<const double> radii, double skin) {
  const std::size_t n = positions.size();
  origin_ = Vec3(medianOf(positions, 0), medianOf(positions, 1), medianOf(positions, 2));
  double smallest = 0.0;
  double largestFinite = 0.0;
  for (const double r : radii) {
    if (r > 0.0 && std::isfinite(r)) smallest = smallest > 0.0 ? std::min(smallest, r) : r;
    if (std::isfinite(r)) largestFinite = std::max(largestFinite, r);
  }
  levels_.clear();
  const auto addLevel = [&](double largest) {
    Level& l = levels_.emplace_back();
    const double edge = 2.0 * largest + skin;
    l.cell_size = edge > 0.0 && std::isfinite(edge) ? edge : 1.0;
    l.inv_cell_size = 1.0 / l.cell_size;
    l.partner_reach = largest + skin;
  };
  // Every radius within a factor 2 of the smallest (a monodisperse or narrow bed): one
  // level, without the per-slot classes below (fl(r / smallest) grows with r, so every
  // class is 0 when the largest's is).
  if (n > 0 && (smallest == 0.0 || largestFinite / smallest < 2.0)) {
    addLevel(largestFinite);
    level_of_slot_.assign(n, 0);
    std::vector<std::uint32_t> all(n);
    for (std::size_t i = 0; i < n; ++i) all[i] = static_cast<std::uint32_t>(i);
    buildLevel(levels_.front(), positions, all);
    return;
  }
  // Radius class of every slot; radii that are not positive and finite join the smallest.
  std::array<double, kMaxLevels> largest{};
  std::array<std::uint32_t, kMaxLevels> members{};
  std::vector<std::uint8_t> classOf(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = radii[i];
    int k = 0;
    if (smallest > 0.0 && r > smallest && std::isfinite(r)) {
      k = std::min(kMaxLevels - 1, static_cast<int>(std::floor(std::log2(r / smallest))));
    }
    classOf[i] = static_cast<std::uint8_t>(k);
    if (std::isfinite(r)) largest[k] = std::max(largest[k], r);
    ++members[k];
  }
  std::array<std::uint8_t, kMaxLevels> levelOfClass{};
  for (int k = 0; k < kMaxLevels; ++k) {
    if (members[k] == 0) continue;
    levelOfClass[k] = static_cast<std::uint8_t>(levels_.size());
    addLevel(largest[k]);
  }
  level_of_slot_.resize(n);
  std::vector<std::vector<std::uint32_t>> slotsOf(levels_.size());
  for (std::size_t i = 0; i < n; ++i) {
    level_of_slot_[i] = levelOfClass[classOf[i]];
    slotsOf[level_of_slot_[i]].push_back(static_cast<std::uint32_t>(i));
  }
  for (std::size_t level = 0; level < levels_.size(); ++level) buildLevel(levels_[level], positions, slotsOf[level]);
}

void CellGrid::buildLevel(Level& l, std::span<const Vec3> positions, std::span<const std::uint32_t> members) {
  std::vector<KeyedSlot> keyed(members.size());
  for (std::size_t k = 0; k < members.size(); ++k) {
    const auto c = coords(l, positions[members[k]]);
    keyed[k] = {pack(c[0], c[1], c[2]), members[k]};
  }
  sortByCell(keyed);
  l.keys.clear();
  l.start.clear();
  l.slots.resize(keyed.size());
  l.lowest = {kCoordLimit, kCoordLimit, kCoordLimit};
  l.highest = {-1, -1, -1};
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    l.slots[k] = keyed[k].slot;
    if (k > 0 && keyed[k].key == keyed[k - 1].key) continue;
    l.keys.push_back(keyed[k].key);
    l.start.push_back(static_cast<std::uint32_t>(k));
    const auto c = unpack(keyed[k].key);
    for (int d = 0; d < 3; ++d) {
      l.lowest[d] = std::min(l.lowest[d], c[d]);
      l.highest[d] = std::max(l.highest[d], c[d]);
    }
  }
  l.start.push_back(static_cast<std::uint32_t>(keyed.size()));
  buildOccupancy(l);
  // At most a quarter full: a lookup of an empty cell probes ~1.4 slots on average,
  // against ~2.5 half full (1:10 bed of 5,000 spheres, before the occupancy bitmap took
  // most empty-cell lookups: 4.6 -> 5.3e7 particle-steps/s); 4 bytes more per cell.
  const std::size_t size = std::bit_ceil(std::max<std::size_t>(2, 4 * l.keys.size()));
  l.mask = size - 1;
  l.table.assign(size, kNoCell);
  for (std::uint32_t cell = 0; cell < l.keys.size(); ++cell) {
    std::uint64_t h = hash(l.keys[cell]) & l.mask;
    while (l.table[h] != kNoCell) h = (h + 1) & l.mask;
    l.table[h] = cell;
  }
}

void CellGrid::buildOccupancy(Level& l) {
  l.occupied.clear();
  if (l.keys.empty()) return;
  std::uint64_t cells = 1;
  for (int d = 0; d < 3; ++d) {
    l.extent[d] = l.highest[d] - l.lowest[d] + 1;
    cells *= static_cast<std::uint64_t>(l.extent[d]);
    // Sparse (far outliers): no bitmap, the hash alone (checked per axis: no overflow).
    if (cells > kOccupancyBitsPerCell * l.keys.size()) return;
  }
  l.occupied.assign((cells + 63) / 64, 0);
  for (const std::uint64_t key : l.keys) {
    const std::uint64_t bit = occupancyBit(l, unpack(key));
    l.occupied[bit >> 6] |= std::uint64_t{1} << (bit & 63);
  }
}

std::vector<std::uint32_t> CellGrid::spatialOrder(std::span<const Vec3> positions) const {
  std::vector<std::uint32_t> order;
  if (levels_.empty()) return order;
  // Cells of the largest level (2 r_max + skin) from the particles' lowest corner, by
  // division: the order the dense grid gave, so a scene's slot order, and with it its
  // trajectory's bits, did not change with the sparse grid. Far outliers below the rest
  // move the corner no further than 2^20 cells from the median (they share the border).
  const double cell = levels_.back().cell_size;
  constexpr double kHalf = static_cast<double>(kCoordLimit / 2);
  Vec3 lo = origin_;
  for (const Vec3& x : positions) {
    for (int d = 0; d < 3; ++d) {
      if (std::isfinite(x[d])) lo[d] = std::min(lo[d], x[d]);
    }
  }
  for (int d = 0; d < 3; ++d) lo[d] = std::max(lo[d], origin_[d] - kHalf * cell);
  const auto cellOf = [&](std::size_t i, int d) -> std::int64_t {
    const double k = std::floor((positions[i][d] - lo[d]) / cell);
    return !(k > 0.0) ? 0 : (k >= 2.0 * kHalf - 1.0 ? kCoordLimit - 1 : static_cast<std::int64_t>(k));
  };
  const std::size_t n = positions.size();
  // The axis whose fullest layer of cells holds the fewest particles varies slowest
  // (ties keep z, then y, slowest): see the header.
  std::array<std::size_t, 3> fullest{};
  for (int d = 0; d < 3; ++d) fullest[d] = fullestLayer(n, [&](std::size_t i) { return cellOf(i, d); });
  std::array<int, 3> axis{0, 1, 2};  // fastest to slowest
  std::stable_sort(axis.begin(), axis.end(), [&](int a, int b) { return fullest[a] > fullest[b]; });
  std::vector<KeyedSlot> keyed(n);
  for (std::size_t i = 0; i < n; ++i) {
    keyed[i] = {pack(cellOf(i, axis[0]), cellOf(i, axis[1]), cellOf(i, axis[2])), static_cast<std::uint32_t>(i)};
  }
  sortByCell(keyed);
  order.reserve(keyed.size());
  for (const KeyedSlot& k : keyed) order.push_back(k.slot);
  return order;
}

std::size_t CellGrid::bytes() const {
  std::size_t total = levels_.capacity() * sizeof(Level) + level_of_slot_.capacity();
  for (const Level& l : levels_) {
    total += l.keys.capacity() * sizeof(std::uint64_t) +
             (l.start.capacity() + l.slots.capacity() + l.table.capacity()) * sizeof(std::uint32_t) +
             l.occupied.capacity() * sizeof(std::uint64_t);
  }
  return total;
}

}  // namespace demlink::core
