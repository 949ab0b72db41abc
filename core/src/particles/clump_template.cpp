/// Mass properties of a union of spheres by a ray quadrature (clump_template.hpp).
///
/// For member i (centre c, radius R) and a direction u, the ray c + t u, t in
/// [0, R], is cut at the points where it enters or leaves other members (roots of
/// a quadratic). On each piece the number of members covering it is constant, and
/// the piece contributes with weight 1/count, so every point of the union is
/// counted once in total over the members. The radial integrals of t^2, t^3, t^4
/// are exact; the directions use Gauss-Legendre in cos(theta) and the trapezoid
/// rule in phi (exact for the polynomial integrands of an uncut ray). The error
/// therefore comes only from directions whose ray is cut, where the radial
/// integral has square-root kinks at grazing rays.
#include "demlink/core/particles/clump_template.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/geometry/principal_axes.hpp"

namespace demlink::core {
namespace {

/// Gauss-Legendre nodes and weights on [-1, 1] (Newton on the three-term recurrence).
void gaussLegendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
  nodes.assign(static_cast<std::size_t>(n), 0.0);
  weights.assign(static_cast<std::size_t>(n), 0.0);
  for (int k = 0; k < (n + 1) / 2; ++k) {
    double x = std::cos(std::numbers::pi * (k + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0;
      double p1 = x;
      for (int j = 2; j <= n; ++j) {
        const double p2 = ((2.0 * j - 1.0) * x * p1 - (j - 1.0) * p0) / j;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / derivative;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    const double w = 2.0 / ((1.0 - x * x) * derivative * derivative);
    const auto a = static_cast<std::size_t>(k);
    const auto b = static_cast<std::size_t>(n - 1 - k);
    nodes[a] = x;
    nodes[b] = -x;
    weights[a] = w;
    weights[b] = w;
  }
}

}  // namespace

UnionMoments unionMoments(const std::vector<ClumpSphere>& spheres, int directions) {
  UnionMoments out;
  if (spheres.empty() || directions < 2) return out;
  // Work relative to the first centre so far-off templates lose no digits.
  const Vec3 origin = spheres.front().offset;
  std::vector<double> mu;
  std::vector<double> muWeight;
  gaussLegendre(directions, mu, muWeight);
  const int phiCount = 2 * directions;
  const double phiWeight = 2.0 * std::numbers::pi / phiCount;

  // The direction grid is turned by a fixed generic rotation: a pair of spheres
  // along a coordinate axis (common in templates) would otherwise put the cut
  // cone's edge along one row of nodes, the quadrature's worst case.
  const Mat3 grid = Eigen::AngleAxisd(1.0, Vec3(0.36, 0.48, 0.8)).toRotationMatrix();
  double volume = 0.0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  std::vector<std::size_t> others;
  std::vector<std::pair<double, double>> cuts;
  std::vector<double> breaks;
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const Vec3 c = spheres[i].offset - origin;
    const double radius = spheres[i].radius;
    others.clear();
    for (std::size_t j = 0; j < spheres.size(); ++j) {
      if (j == i) continue;
      const double reach = radius + spheres[j].radius;
      if ((spheres[j].offset - spheres[i].offset).squaredNorm() < reach * reach) others.push_back(j);
    }
    double s2 = 0.0;          // sum of weight * integral t^2 dt
    Vec3 s3 = Vec3::Zero();   // sum of weight * u * integral t^3 dt
    Mat3 s4 = Mat3::Zero();   // sum of weight * u u^T * integral t^4 dt
    for (int a = 0; a < directions; ++a) {
      const double cosTheta = mu[static_cast<std::size_t>(a)];
      const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
      for (int b = 0; b < phiCount; ++b) {
        const double phi = (b + 0.5) * phiWeight;
        const Vec3 u = grid * Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
        const double w = muWeight[static_cast<std::size_t>(a)] * phiWeight;
        cuts.clear();
        breaks.assign({0.0, radius});
        for (const std::size_t j : others) {
          const Vec3 rel = spheres[i].offset - spheres[j].offset;
          const double half = u.dot(rel);
          const double disc = half * half - (rel.squaredNorm() - spheres[j].radius * spheres[j].radius);
          if (disc <= 0.0) continue;
          const double root = std::sqrt(disc);
          const double t1 = std::max(0.0, -half - root);
          const double t2 = std::min(radius, -half + root);
          if (!(t1 < t2)) continue;
          cuts.emplace_back(t1, t2);
          breaks.push_back(t1);
          breaks.push_back(t2);
        }
        double i2 = 0.0;
        double i3 = 0.0;
        double i4 = 0.0;
        if (cuts.empty()) {
          i2 = radius * radius * radius / 3.0;
          i3 = i2 * radius * 0.75;
          i4 = i2 * radius * radius * 0.6;
        } else {
          std::sort(breaks.begin(), breaks.end());
          for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
            const double lo = breaks[k];
            const double hi = breaks[k + 1];
            if (!(hi > lo)) continue;
            const double mid = 0.5 * (lo + hi);
            int count = 1;
            for (const auto& [t1, t2] : cuts) count += (mid > t1 && mid < t2) ? 1 : 0;
            const double weight = 1.0 / count;
            i2 += weight * (hi * hi * hi - lo * lo * lo) / 3.0;
            i3 += weight * (hi * hi * hi * hi - lo * lo * lo * lo) / 4.0;
            i4 += weight * (hi * hi * hi * hi * hi - lo * lo * lo * lo * lo) / 5.0;
          }
        }
        s2 += w * i2;
        s3 += (w * i3) * u;
        s4 += (w * i4) * (u * u.transpose());
      }
    }
    // Sphere i's share: integrals of 1, x and x x^T over its pieces (x = c + t u).
    volume += s2;
    first += c * s2 + s3;
    second += c * c.transpose() * s2 + c * s3.transpose() + s3 * c.transpose() + s4;
  }
  out.volume = volume;
  if (!(volume > 0.0)) return out;
  const Vec3 centroid = first / volume;
  out.centroid = centroid + origin;
  out.second = second - volume * centroid * centroid.transpose();
  out.second = 0.5 * (out.second + out.second.transpose()).eval();
  return out;
}

ClumpTemplate::ClumpTemplate(std::string name, std::vector<ClumpSphere> spheres, const std::string& fieldPrefix)
    : name_(std::move(name)), spheres_(std::move(spheres)) {
  if (spheres_.empty()) throw InputError(fieldPrefix + ".spheres", "[]", "a clump template needs at least one sphere");
  if (spheres_.size() > kMaxClumpTemplateSpheres) {
    throw InputError(fieldPrefix + ".spheres", std::to_string(spheres_.size()) + " spheres",
                     "at most " + std::to_string(kMaxClumpTemplateSpheres) + " spheres in one clump template");
  }
  for (std::size_t k = 0; k < spheres_.size(); ++k) {
    const std::string path = fieldPrefix + ".spheres[" + std::to_string(k) + "]";
    for (int axis = 0; axis < 3; ++axis) {
      requireFinite(path + ".offset[" + std::to_string(axis) + "]", spheres_[k].offset[axis]);
    }
    requirePositive(path + ".radius", spheres_[k].radius);
  }
  const UnionMoments moments = unionMoments(spheres_);
  if (!(moments.volume > 0.0) || !std::isfinite(moments.volume) || !moments.second.allFinite()) {
    throw InputError(fieldPrefix + ".spheres", formatValue(moments.volume) + " m^3",
                     "the union of the spheres has no usable volume (radii too small or offsets too large)");
  }
  volume_ = moments.volume;
  com_ = moments.centroid;
  inertia_ = moments.second.trace() * Mat3::Identity() - moments.second;
  const PrincipalAxes principal = principalAxes(inertia_);
  moments_ = principal.moments;
  principal_ = Quat(principal.axes).normalized();
  const Mat3 toBody = principal_.toRotationMatrix().transpose();
  min_radius_ = spheres_.front().radius;
  for (const ClumpSphere& sphere : spheres_) {
    const ClumpSphere body{toBody * (sphere.offset - com_), sphere.radius};
    body_spheres_.push_back(body);
    bounding_radius_ = std::max(bounding_radius_, body.offset.norm() + body.radius);
    min_radius_ = std::min(min_radius_, sphere.radius);
  }
}

}  // namespace demlink::core
