#pragma once
/// When may the Verlet list (and the plane near lists built with it) have missed a
/// contact? The classic rule rebuilds when any particle has moved skin/2 since the
/// build. It watches absolute motion, so a column falling as one body, a belt of
/// particles riding along, or a bed being carried rebuilds as often as an impact does.
///
/// This guard watches relative motion instead. A pair left out of the list was more
/// than r_i + r_j + skin apart at the build, so it can touch only after its relative
/// displacement |d_i - d_j| (d = x - x_build) exceeds the skin. Consecutive slots are
/// close in space (World keeps them in cell order), so the guard takes groups of
/// kGroupSlots slots, the box of their build positions and, each step, the box of their
/// displacements:
///   - two groups whose build boxes were within `reach` = 2 (2 r_max + skin) of each
///     other: the largest relative displacement of any of their particles, bounded by
///     the two displacement boxes, must stay within the skin;
///   - any other two groups were at least `reach` apart, so their particles cannot touch
///     while every displacement lies in one box of diagonal <= reach - 2 r_max;
///   - a plane: a particle not in its near list was more than skin from it; per group
///     the smallest such gap plus the displacement box's largest approach must stay >= 0.
/// Each bound is exact or conservative, so the list is never stale when the guard says
/// it is fresh. Moving meshes and deformable surfaces keep their own near lists, which
/// assume the skin/2 rule; World uses the classic rule when a scene has them.
#include <cstdint>
#include <span>
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/parallel/thread_pool.hpp"

namespace demlink::core {

class RebuildGuard {
 public:
  /// Consecutive slots per group: small enough that a group's displacement box stays
  /// tight, large enough that the near group pairs are few.
  static constexpr std::uint32_t kGroupSlots = 64;

  /// Arms the guard for a list just built from `built` (positions at the build, one per
  /// row) with `radius` per slot and the list's `skin`; forgets any planes.
  void arm(std::span<const Vec3> built, std::span<const double> radius, double skin);

  /// Adds a plane (a point on it, its unit normal towards the particles) whose near list
  /// `nearSlots` (ascending) was built with the same skin and build positions.
  void addPlane(const Vec3& point, const Vec3& normal, std::span<const std::uint32_t> nearSlots,
                std::span<const Vec3> built, std::span<const double> radius);

  /// True when some pair or plane contact may be missing from the lists at positions
  /// `now` (built: the positions the guard was armed with). Also true when unarmed or the
  /// particle count differs. The answer does not depend on the thread count.
  [[nodiscard]] bool stale(std::span<const Vec3> built, std::span<const Vec3> now, ThreadPool* pool = nullptr) const;

  /// Near group pairs (g < h) of the last arm(), for tests and the report.
  [[nodiscard]] std::size_t nearPairCount() const { return near_.size(); }

 private:
  struct Box {
    Vec3 lo;
    Vec3 hi;
  };
  struct NearPair {
    std::uint32_t a;
    std::uint32_t b;
  };
  struct PlaneGaps {
    Vec3 normal;
    std::vector<double> smallest_gap;  ///< per group, of the particles not in the near list [m]
  };

  /// The box of the displacements now - built of slots [begin, end).
  static Box displacementBox(std::span<const Vec3> built, std::span<const Vec3> now, std::size_t begin,
                             std::size_t end);

  bool armed_ = false;
  std::size_t count_ = 0;
  double skin_ = 0.0;
  double far_extent_ = 0.0;  ///< largest diagonal of all displacements while far groups cannot meet [m]
  std::vector<NearPair> near_;
  std::vector<PlaneGaps> planes_;
  mutable std::vector<Box> moved_;  ///< per group, the box of displacements (scratch of stale())
};

}  // namespace demlink::core
