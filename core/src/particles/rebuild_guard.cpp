#include "demlink/core/particles/rebuild_guard.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

#include "demlink/core/parallel/parallel_loops.hpp"

namespace demlink::core {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
static_assert(sizeof(Vec3) == 3 * sizeof(double), "displacementBox reads the position columns as flat arrays");

std::size_t groupCount(std::size_t n) { return (n + RebuildGuard::kGroupSlots - 1) / RebuildGuard::kGroupSlots; }

std::size_t groupBegin(std::size_t g) { return g * RebuildGuard::kGroupSlots; }

/// A box of no points (every particle of its group non-finite): such a particle
/// touches nothing, so its group is left out of every test.
template <class Box>
bool isEmpty(const Box& b) {
  return !(b.lo[0] <= b.hi[0]);
}

/// Squared Euclidean distance between two axis-aligned boxes (0 when they overlap).
double boxDistance2(const Vec3& loA, const Vec3& hiA, const Vec3& loB, const Vec3& hiB) {
  double d2 = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double gap = std::max({0.0, loB[d] - hiA[d], loA[d] - hiB[d]});
    d2 += gap * gap;
  }
  return d2;
}

/// Squared bound on |a - b| for a in box A and b in box B (per axis the farther corner).
double largestSeparation2(const Vec3& loA, const Vec3& hiA, const Vec3& loB, const Vec3& hiB) {
  double d2 = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double span = std::max(hiA[d] - loB[d], hiB[d] - loA[d]);
    d2 += span * span;
  }
  return d2;
}

}  // namespace

RebuildGuard::Box RebuildGuard::displacementBox(std::span<const Vec3> built, std::span<const Vec3> now,
                                                std::size_t begin, std::size_t end) {
  // Over the coordinates as one flat array, two particles (six lanes) at a time, so
  // the compiler can use packed minima and maxima; lane l holds axis l % 3. Written as
  // d < lo ? d : lo, a NaN displacement (a failed run, which the watchdog reports)
  // leaves the box as it is: such a particle touches nothing.
  const double* x = now.data()->data() + 3 * begin;
  const double* x0 = built.data()->data() + 3 * begin;
  const std::size_t values = 3 * (end - begin);
  std::array<double, 6> lo;
  std::array<double, 6> hi;
  lo.fill(kInf);
  hi.fill(-kInf);
  std::size_t k = 0;
  for (; k + 6 <= values; k += 6) {
    for (std::size_t l = 0; l < 6; ++l) {
      const double d = x[k + l] - x0[k + l];
      lo[l] = d < lo[l] ? d : lo[l];
      hi[l] = d > hi[l] ? d : hi[l];
    }
  }
  for (; k < values; ++k) {
    const double d = x[k] - x0[k];
    lo[k % 3] = d < lo[k % 3] ? d : lo[k % 3];
    hi[k % 3] = d > hi[k % 3] ? d : hi[k % 3];
  }
  Box box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = std::min(lo[a], lo[a + 3]);
    box.hi[a] = std::max(hi[a], hi[a + 3]);
  }
  return box;
}

void RebuildGuard::arm(std::span<const Vec3> built, std::span<const double> radius, double skin) {
  armed_ = false;
  near_.clear();
  planes_.clear();
  count_ = built.size();
  skin_ = skin;
  const std::size_t n = built.size();
  if (radius.size() < n || !(skin >= 0.0)) return;
  // A particle at a non-finite position (a failed run, which the watchdog reports)
  // compares false with everything, so it never touches: it is left out.
  double largest = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (built[i].allFinite() && std::isfinite(radius[i])) largest = std::max(largest, radius[i]);
  }
  const double reach = 2.0 * (2.0 * largest + skin);
  far_extent_ = reach - 2.0 * largest;

  const std::size_t groups = groupCount(n);
  std::vector<Box> box(groups, Box{Vec3::Constant(kInf), Vec3::Constant(-kInf)});
  for (std::size_t i = 0; i < n; ++i) {
    if (!built[i].allFinite()) continue;
    Box& b = box[i / kGroupSlots];
    b.lo = b.lo.cwiseMin(built[i]);
    b.hi = b.hi.cwiseMax(built[i]);
  }
  // Sweep along the axis of the largest extent: groups ordered by their low end there,
  // each compared with those starting within its high end plus reach.
  Vec3 lo = Vec3::Constant(kInf);
  Vec3 hi = Vec3::Constant(-kInf);
  std::vector<std::uint32_t> order;
  for (std::uint32_t g = 0; g < groups; ++g) {
    if (isEmpty(box[g])) continue;
    order.push_back(g);
    lo = lo.cwiseMin(box[g].lo);
    hi = hi.cwiseMax(box[g].hi);
  }
  int axis = 0;
  if (!order.empty()) (hi - lo).maxCoeff(&axis);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return box[a].lo[axis] != box[b].lo[axis] ? box[a].lo[axis] < box[b].lo[axis] : a < b;
  });
  const double reach2 = reach * reach;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const Box& a = box[order[k]];
    for (std::size_t m = k + 1; m < order.size() && box[order[m]].lo[axis] < a.hi[axis] + reach; ++m) {
      const Box& b = box[order[m]];
      if (boxDistance2(a.lo, a.hi, b.lo, b.hi) < reach2) {
        near_.push_back({std::min(order[k], order[m]), std::max(order[k], order[m])});
      }
    }
  }
  moved_.resize(groups);
  armed_ = true;
}

void RebuildGuard::addPlane(const Vec3& point, const Vec3& normal, std::span<const std::uint32_t> nearSlots,
                            std::span<const Vec3> built, std::span<const double> radius) {
  if (!armed_) return;
  PlaneGaps& plane = planes_.emplace_back();
  plane.normal = normal;
  plane.smallest_gap.assign(groupCount(count_), kInf);
  std::size_t next = 0;  // nearSlots is ascending
  for (std::size_t i = 0; i < count_; ++i) {
    if (next < nearSlots.size() && nearSlots[next] == i) {
      ++next;
      continue;
    }
    double& smallest = plane.smallest_gap[i / kGroupSlots];
    smallest = std::min(smallest, (built[i] - point).dot(normal) - radius[i]);
  }
}

bool RebuildGuard::stale(std::span<const Vec3> built, std::span<const Vec3> now, ThreadPool* pool) const {
  if (!armed_ || now.size() != count_ || built.size() != count_) return true;
  const std::size_t groups = moved_.size();
  if (groups == 0) return false;
  const std::uint32_t chunks = chunkCount(groups, kChunkElements / kGroupSlots);
  parallelParts(pool, chunks, [&](std::uint32_t chunk) {
    for (std::size_t g = chunkBegin(groups, chunks, chunk); g < chunkBegin(groups, chunks, chunk + 1); ++g) {
      moved_[g] = displacementBox(built, now, groupBegin(g), std::min(count_, groupBegin(g + 1)));
    }
  });
  const double skin2 = skin_ * skin_;
  Vec3 lo = Vec3::Constant(kInf);
  Vec3 hi = Vec3::Constant(-kInf);
  for (const Box& b : moved_) {
    if (isEmpty(b)) continue;
    if (!(largestSeparation2(b.lo, b.hi, b.lo, b.hi) <= skin2)) return true;
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  if (lo[0] <= hi[0] && !((hi - lo).squaredNorm() <= far_extent_ * far_extent_)) return true;
  // The near group pairs, then every plane's groups, as one parallel loop (they were a
  // serial tenth of a 50,000-particle step on two threads). The answer is an "or" over
  // all tests, so it does not depend on which thread ran which test.
  const std::size_t pairTests = near_.size();
  std::atomic<bool> found{false};
  parallelChunks(pool, pairTests + planes_.size() * groups, [&](std::size_t begin, std::size_t end) {
    bool missed = false;
    for (std::size_t k = begin; k < std::min(end, pairTests); ++k) {
      const Box& a = moved_[near_[k].a];
      const Box& b = moved_[near_[k].b];
      if (isEmpty(a) || isEmpty(b)) continue;
      missed = missed || !(largestSeparation2(a.lo, a.hi, b.lo, b.hi) <= skin2);
    }
    for (std::size_t k = std::max(begin, pairTests); k < end; ++k) {
      // The displacement in the box that approaches the plane most.
      const PlaneGaps& plane = planes_[(k - pairTests) / groups];
      const std::size_t g = (k - pairTests) % groups;
      const Box& b = moved_[g];
      if (isEmpty(b)) continue;
      double approach = 0.0;
      for (int d = 0; d < 3; ++d) approach += plane.normal[d] * (plane.normal[d] > 0.0 ? b.lo[d] : b.hi[d]);
      missed = missed || !(plane.smallest_gap[g] + approach >= 0.0);
    }
    if (missed) found.store(true, std::memory_order_relaxed);
  });
  return found.load(std::memory_order_relaxed);
}

}  // namespace demlink::core
