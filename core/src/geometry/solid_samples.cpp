/// Grid sampling of a closed mesh's inside and depth (solid_samples.hpp).
#include "demlink/core/geometry/solid_samples.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "demlink/core/geometry/triangle_geometry.hpp"

namespace demlink::core {
namespace {

/// Fractions of a cell the samples are shifted by (fractional parts of multiples of the
/// golden ratio: far from any simple fraction a mesh's coordinates are likely to use).
constexpr std::array<double, 3> kGenericShift{0.0618034, 0.0236068, 0.0854102};

/// Stands for "no outside sample on this line yet" in the squared distances (cells^2).
constexpr double kFar = 1e12;

/// z component of (q - p) x (x - p) in the xy plane.
double orient2d(const Vec3& p, const Vec3& q, double x, double y) {
  return (q.x() - p.x()) * (y - p.y()) - (q.y() - p.y()) * (x - p.x());
}

/// One line of the squared distance transform (unit spacing): out[q] = min_p (q - p)^2 + f[p].
/// The lower envelope of the parabolas rooted at each p (Felzenszwalb and Huttenlocher).
void distanceTransform1d(const std::vector<double>& f, std::vector<double>& out, std::vector<std::size_t>& v,
                         std::vector<double>& z) {
  const std::size_t n = f.size();
  v.assign(n, 0);
  z.assign(n + 1, 0.0);
  std::size_t k = 0;
  z[0] = -std::numeric_limits<double>::infinity();
  z[1] = std::numeric_limits<double>::infinity();
  const auto meet = [&f](std::size_t q, std::size_t p) {
    const double dq = static_cast<double>(q);
    const double dp = static_cast<double>(p);
    return ((f[q] + dq * dq) - (f[p] + dp * dp)) / (2.0 * dq - 2.0 * dp);
  };
  for (std::size_t q = 1; q < n; ++q) {
    double s = meet(q, v[k]);
    while (s <= z[k]) {
      --k;
      s = meet(q, v[k]);
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  out.assign(n, 0.0);
  k = 0;
  for (std::size_t q = 0; q < n; ++q) {
    while (z[k + 1] < static_cast<double>(q)) ++k;
    const double d = static_cast<double>(q) - static_cast<double>(v[k]);
    out[q] = d * d + f[v[k]];
  }
}

/// Marks the inside samples, one vertical ray per column (see the header).
void classifyInside(const StlMesh& mesh, SolidSamples& s) {
  const std::size_t nx = s.counts[0];
  const std::size_t ny = s.counts[1];
  const std::size_t nz = s.counts[2];
  std::vector<std::vector<std::pair<double, int>>> crossings(nx * ny);
  const auto column = [&s](double coordinate, int axis) {
    return (coordinate - s.origin[axis]) / s.spacing;
  };
  for (const auto& tri : mesh.triangles) {
    const Vec3& a = mesh.vertices[tri[0]];
    const Vec3& b = mesh.vertices[tri[1]];
    const Vec3& c = mesh.vertices[tri[2]];
    const double xLo = std::min({a.x(), b.x(), c.x()});
    const double xHi = std::max({a.x(), b.x(), c.x()});
    const double yLo = std::min({a.y(), b.y(), c.y()});
    const double yHi = std::max({a.y(), b.y(), c.y()});
    const double i0 = std::max(0.0, std::ceil(column(xLo, 0)));
    const double i1 = std::min(static_cast<double>(nx) - 1.0, std::floor(column(xHi, 0)));
    const double j0 = std::max(0.0, std::ceil(column(yLo, 1)));
    const double j1 = std::min(static_cast<double>(ny) - 1.0, std::floor(column(yHi, 1)));
    if (i0 > i1 || j0 > j1) continue;
    // Edge k runs from vertex k to vertex k + 1; evaluated from its lower-index end.
    const std::array<std::uint32_t, 3> id = tri;
    const auto edge = [&](std::size_t k, double x, double y) {
      const std::uint32_t p = id[k];
      const std::uint32_t q = id[(k + 1) % 3];
      const double value = p < q ? orient2d(mesh.vertices[p], mesh.vertices[q], x, y)
                                 : orient2d(mesh.vertices[q], mesh.vertices[p], x, y);
      return p < q ? value : -value;
    };
    for (auto j = static_cast<std::size_t>(j0); j <= static_cast<std::size_t>(j1); ++j) {
      for (auto i = static_cast<std::size_t>(i0); i <= static_cast<std::size_t>(i1); ++i) {
        const Vec3 p = s.point(i, j, 0);
        const double eAB = edge(0, p.x(), p.y());
        const double eBC = edge(1, p.x(), p.y());
        const double eCA = edge(2, p.x(), p.y());
        int sign = 0;
        if (eAB > 0.0 && eBC > 0.0 && eCA > 0.0) sign = 1;
        if (eAB < 0.0 && eBC < 0.0 && eCA < 0.0) sign = -1;
        if (sign == 0) continue;
        // Barycentric weight of a vertex: the edge function of the opposite edge.
        const double zCross = (eBC * a.z() + eCA * b.z() + eAB * c.z()) / (eAB + eBC + eCA);
        crossings[i + nx * j].emplace_back(zCross, sign);
      }
    }
  }
  for (std::size_t j = 0; j < ny; ++j) {
    for (std::size_t i = 0; i < nx; ++i) {
      auto& list = crossings[i + nx * j];
      if (list.empty()) continue;
      std::sort(list.begin(), list.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
      int winding = 0;
      std::size_t next = 0;
      for (std::size_t k = nz; k-- > 0;) {
        const double zSample = s.point(i, j, k).z();
        while (next < list.size() && list[next].first > zSample) winding += list[next++].second;
        s.inside[i + nx * (j + ny * k)] = winding > 0 ? 1 : 0;
      }
    }
  }
}

/// Depth of every inside sample: the separable squared distance transform along x, y, z,
/// each line padded with an outside sample at both ends.
void computeDepth(SolidSamples& s) {
  const std::array<std::size_t, 3> n = s.counts;
  std::vector<double> squared(s.size());
  for (std::size_t index = 0; index < s.size(); ++index) squared[index] = s.inside[index] != 0 ? kFar : 0.0;
  const std::array<std::size_t, 3> stride{1, n[0], n[0] * n[1]};
  std::vector<double> line;
  std::vector<double> out;
  std::vector<std::size_t> v;
  std::vector<double> z;
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t length = n[static_cast<std::size_t>(axis)];
    const std::size_t step = stride[static_cast<std::size_t>(axis)];
    for (std::size_t start = 0; start < s.size(); ++start) {
      if ((start / step) % length != 0) continue;  // only the first sample of each line
      line.assign(length + 2, 0.0);
      for (std::size_t q = 0; q < length; ++q) line[q + 1] = squared[start + q * step];
      distanceTransform1d(line, out, v, z);
      for (std::size_t q = 0; q < length; ++q) squared[start + q * step] = out[q + 1];
    }
  }
  s.depth.assign(s.size(), 0.0);
  for (std::size_t index = 0; index < s.size(); ++index) {
    if (s.inside[index] != 0) s.depth[index] = std::sqrt(squared[index]) * s.spacing;
  }
}

}  // namespace

SolidSamples sampleSolid(const StlMesh& mesh, std::size_t cellsAlongLongest) {
  Vec3 lo = mesh.vertices.front();
  Vec3 hi = lo;
  for (const Vec3& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  SolidSamples s;
  const double longest = (hi - lo).maxCoeff();
  s.spacing = longest / static_cast<double>(std::max<std::size_t>(cellsAlongLongest, 2));
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    const double extent = hi[axis] - lo[axis];
    s.counts[a] = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(extent / s.spacing)));
    s.origin[axis] = lo[axis] + (0.5 + kGenericShift[a]) * s.spacing;
  }
  s.inside.assign(s.counts[0] * s.counts[1] * s.counts[2], 0);
  classifyInside(mesh, s);
  computeDepth(s);
  return s;
}

double distanceToSurface(const StlMesh& mesh, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& tri : mesh.triangles) {
    const ClosestPoint closest =
        closestPointOnTriangle(p, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
    best = std::min(best, (closest.point - p).squaredNorm());
  }
  return std::sqrt(best);
}

}  // namespace demlink::core
