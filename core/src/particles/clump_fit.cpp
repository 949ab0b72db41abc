/// Greedy medial-axis sphere fit of a closed mesh (clump_fit.hpp).
#include "demlink/core/particles/clump_fit.hpp"

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <limits>

namespace demlink::core {
namespace {

/// Directions of the union-volume quadrature while matching the volume: the union changes
/// smoothly with the scale, so a coarse grid finds the factor; the report uses the full one.
constexpr int kMatchDirections = 64;

std::vector<ClumpSphere> scaled(const std::vector<ClumpSphere>& spheres, double factor) {
  std::vector<ClumpSphere> out = spheres;
  for (ClumpSphere& sphere : out) sphere.radius *= factor;
  return out;
}

/// The inside samples no sphere covers yet, with their running sum for their centroid.
class Uncovered {
 public:
  explicit Uncovered(const SolidSamples& samples) : samples_(samples), covered_(samples.size(), 0) {
    for (std::size_t index = 0; index < samples.size(); ++index) {
      if (samples.inside[index] != 0) {
        sum_ += samples.point(index);
        ++count_;
      }
    }
  }
  [[nodiscard]] bool covered(std::size_t index) const { return covered_[index] != 0; }
  [[nodiscard]] Vec3 centroid() const { return count_ > 0 ? Vec3(sum_ / static_cast<double>(count_)) : Vec3::Zero(); }

  /// Marks one sample as covered.
  void mark(std::size_t index) {
    if (covered_[index] != 0) return;
    covered_[index] = 1;
    if (samples_.inside[index] != 0) {
      sum_ -= samples_.point(index);
      --count_;
    }
  }
  /// Marks every sample whose point lies inside the sphere.
  void cover(const ClumpSphere& sphere) {
    forEachIn(sphere, 1, [this](std::size_t index) { mark(index); });
  }
  /// How many uncovered inside samples the sphere would cover, counted on every
  /// `stride`-th sample along each axis (so a large sphere costs at most ~ (2 x 8)^3).
  [[nodiscard]] double gain(const ClumpSphere& sphere) const {
    const double stride = std::max(1.0, std::floor(sphere.radius / (8.0 * samples_.spacing)));
    std::size_t found = 0;
    forEachIn(sphere, static_cast<std::size_t>(stride), [this, &found](std::size_t index) {
      if (covered_[index] == 0 && samples_.inside[index] != 0) ++found;
    });
    return static_cast<double>(found) * stride * stride * stride;
  }

 private:
  template <typename Visit>
  void forEachIn(const ClumpSphere& sphere, std::size_t stride, Visit&& visit) const {
    std::array<std::size_t, 3> lo{};
    std::array<std::size_t, 3> hi{};
    for (int axis = 0; axis < 3; ++axis) {
      const auto a = static_cast<std::size_t>(axis);
      const double count = static_cast<double>(samples_.counts[a]);
      const double first = (sphere.offset[axis] - sphere.radius - samples_.origin[axis]) / samples_.spacing;
      const double last = (sphere.offset[axis] + sphere.radius - samples_.origin[axis]) / samples_.spacing;
      lo[a] = static_cast<std::size_t>(std::clamp(std::ceil(first), 0.0, count));
      hi[a] = static_cast<std::size_t>(std::clamp(std::floor(last) + 1.0, 0.0, count));
    }
    const double r2 = sphere.radius * sphere.radius;
    for (std::size_t k = lo[2]; k < hi[2]; k += stride) {
      for (std::size_t j = lo[1]; j < hi[1]; j += stride) {
        for (std::size_t i = lo[0]; i < hi[0]; i += stride) {
          if ((samples_.point(i, j, k) - sphere.offset).squaredNorm() <= r2) {
            visit(i + samples_.counts[0] * (j + samples_.counts[1] * k));
          }
        }
      }
    }
  }

  const SolidSamples& samples_;
  std::vector<std::uint8_t> covered_;
  Vec3 sum_ = Vec3::Zero();
  std::size_t count_ = 0;
};

/// Moves the centre by at most `reach` to where it is farther from the surface (a pattern
/// search with halving steps). Only for spheres larger than `reach`: every point the centre
/// may move to is then inside the solid, so the unsigned distance is the depth.
ClumpSphere refined(const StlMesh& mesh, ClumpSphere sphere, double reach) {
  if (!(sphere.radius > reach)) return sphere;
  const Vec3 start = sphere.offset;
  double step = 0.5 * reach;
  for (int iteration = 0; iteration < 200 && step > reach / 64.0; ++iteration) {
    bool improved = false;
    for (int axis = 0; axis < 3 && !improved; ++axis) {
      for (const double sign : {1.0, -1.0}) {
        Vec3 centre = sphere.offset;
        centre[axis] += sign * step;
        if ((centre - start).norm() > reach) continue;
        const double radius = distanceToSurface(mesh, centre);
        if (radius > sphere.radius) {
          sphere = {centre, radius};
          improved = true;
          break;
        }
      }
    }
    if (!improved) step *= 0.5;
  }
  return sphere;
}

struct Candidate {
  ClumpSphere sphere;
  double gain = 0.0;  ///< uncovered samples it covers [-]
  /// Which of two candidates that cover as much wins, the larger: before the first sphere,
  /// minus the distance to the uncovered samples' centroid; after it, the distance to the
  /// nearest placed centre [m].
  double spread = 0.0;
};

}  // namespace

std::vector<ClumpSphere> inscribedSpheres(const StlMesh& mesh, const SolidSamples& samples, std::size_t count) {
  std::vector<std::size_t> order;
  for (std::size_t index = 0; index < samples.size(); ++index) {
    if (samples.inside[index] != 0) order.push_back(index);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&samples](std::size_t a, std::size_t b) { return samples.depth[a] > samples.depth[b]; });
  const std::size_t budget = std::clamp<std::size_t>(kClumpFitDistanceBudget / std::max<std::size_t>(mesh.triangles.size(), 1),
                                                     kMinClumpFitCandidates, kMaxClumpFitCandidates);
  Uncovered uncovered(samples);
  std::vector<ClumpSphere> spheres;
  std::vector<std::size_t> band;
  std::vector<Candidate> candidates;
  std::size_t next = 0;
  while (spheres.size() < count) {
    while (next < order.size() && uncovered.covered(order[next])) ++next;
    if (next == order.size()) break;
    // The band: uncovered samples within one spacing of the largest depth; when it holds
    // more than the budget, every k-th of them, so the candidates spread over all of it.
    const double depthFloor = samples.depth[order[next]] - samples.spacing;
    band.clear();
    for (std::size_t k = next; k < order.size() && samples.depth[order[k]] >= depthFloor; ++k) {
      if (!uncovered.covered(order[k])) band.push_back(order[k]);
    }
    const std::size_t every = (band.size() + budget - 1) / budget;
    const Vec3 centroid = uncovered.centroid();
    candidates.clear();
    double largest = 0.0;
    for (std::size_t k = 0; k < band.size(); k += every) {
      const Vec3 centre = samples.point(band[k]);
      double spread = -(centre - centroid).norm();
      if (!spheres.empty()) {
        spread = std::numeric_limits<double>::infinity();
        for (const ClumpSphere& placed : spheres) spread = std::min(spread, (centre - placed.offset).norm());
      }
      candidates.push_back({{centre, distanceToSurface(mesh, centre)}, 0.0, spread});
      largest = std::max(largest, candidates.back().sphere.radius);
    }
    if (!(largest > 0.0)) {
      uncovered.mark(order[next]);  // a sample on the surface itself: no sphere fits there
      continue;
    }
    // Among the nearly largest spheres, the one that covers the most of what is still
    // uncovered (so spheres spread over a long or flat medial axis instead of crowding
    // the first one); of equal ones, the first sphere nearest the uncovered centroid (a
    // capsule's in its middle, not at the end of its axis where the sample order starts),
    // later ones farthest from every placed centre (spread over a plate's whole middle).
    std::size_t chosen = candidates.size();
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      Candidate& candidate = candidates[k];
      if (candidate.sphere.radius < largest - 0.5 * samples.spacing) continue;
      candidate.gain = uncovered.gain(candidate.sphere);
      if (chosen == candidates.size() || candidate.gain > candidates[chosen].gain ||
          (candidate.gain == candidates[chosen].gain && candidate.spread > candidates[chosen].spread)) {
        chosen = k;
      }
    }
    const ClumpSphere sphere = refined(mesh, candidates.at(chosen).sphere, samples.spacing);
    spheres.push_back(sphere);
    uncovered.cover(sphere);
  }
  return spheres;
}

double volumeMatchingScale(const std::vector<ClumpSphere>& spheres, double volume) {
  // Secant steps on log V(log s): V grows like s^p with p <= 3 (3 while no sphere overlaps
  // another), p taken from the last two evaluations.
  double scale = 1.0;
  double current = unionMoments(spheres, kMatchDirections).volume;
  double exponent = 3.0;
  for (int iteration = 0; iteration < 50 && std::abs(current / volume - 1.0) > 1e-8; ++iteration) {
    const double nextScale = scale * std::pow(volume / current, 1.0 / exponent);
    const double nextVolume = unionMoments(scaled(spheres, nextScale), kMatchDirections).volume;
    const double measured = std::log(nextVolume / current) / std::log(nextScale / scale);
    if (std::isfinite(measured) && measured > 0.5) exponent = std::min(measured, 3.0);
    scale = nextScale;
    current = nextVolume;
  }
  return scale;
}

double ClumpFitErrors::largest() const {
  return std::max({std::abs(volume), centre_of_mass, principal_moments.cwiseAbs().maxCoeff()});
}

ClumpFitErrors compareWithSolid(const ClumpTemplate& clump, const SolidMassProperties& solid) {
  ClumpFitErrors errors;
  errors.volume = (clump.volume() - solid.volume) / solid.volume;
  errors.centre_of_mass = (clump.centreOfMass() - solid.centroid).norm() / std::cbrt(solid.volume);
  errors.principal_moments =
      (clump.principalMomentsPerDensity() - solid.principal.moments).cwiseQuotient(solid.principal.moments);
  errors.bounding_radius = (clump.boundingRadius() - solid.bounding_radius) / solid.bounding_radius;
  return errors;
}

}  // namespace demlink::core
