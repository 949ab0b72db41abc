#pragma once
// Shared set-up of the FEM body tests: a cantilever beam meshed by boxTetMesh, written to a
// temporary .msh and built into an FemBody, and the loads and probes the tests use.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "demlink/core/deformable/fem_body.hpp"
#include "demlink/core/deformable/tet_mesh.hpp"

namespace demlink::core::fem_test {

/// A directory under the system temp dir, removed with the object.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("demlink_fem_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

/// Cantilever along x: [0, L] x [0, B] x [0, H], clamped at x = 0.
struct Beam {
  double length = 1.0;   // [m]
  double width = 0.05;   // [m]
  double height = 0.05;  // [m]
  int nx = 20;
  int ny = 2;
  int nz = 2;
  int order = 2;
  double youngs_modulus = 1.0e8;  // [Pa]
  double poisson_ratio = 0.3;
  double density = 1000.0;  // [kg/m^3]

  /// A coarser beam: `cells` along x, one across.
  [[nodiscard]] static Beam coarse(int cells) {
    Beam b;
    b.nx = cells;
    b.ny = b.nz = 1;
    return b;
  }

  [[nodiscard]] double area() const { return width * height; }
  [[nodiscard]] double inertia() const { return width * height * height * height / 12.0; }  // about y [m^4]
  /// Euler-Bernoulli tip deflection under a tip load P [N].
  [[nodiscard]] double tipDeflection(double load) const {
    return load * length * length * length / (3.0 * youngs_modulus * inertia());
  }
  /// Euler-Bernoulli first bending frequency [Hz].
  [[nodiscard]] double firstFrequency() const {
    return 1.875104 * 1.875104 *
           std::sqrt(youngs_modulus * inertia() / (density * area() * std::pow(length, 4))) / (2.0 * M_PI);
  }
  [[nodiscard]] TetMesh mesh() const {
    return boxTetMesh(Vec3::Zero(), Vec3(length, width, height), nx, ny, nz, order);
  }
  /// Spec of the clamped beam from the .msh at `path` (written by writeGmsh(path, mesh(), ...)).
  [[nodiscard]] FemSpec spec(const std::string& path) const {
    FemSpec s;
    s.name = "beam";
    s.msh_path = path;
    s.youngs_modulus = youngs_modulus;
    s.poisson_ratio = poisson_ratio;
    s.density = density;
    const double eps = 1e-9;
    s.fixed_regions.push_back({Vec3(-eps, -eps, -eps), Vec3(eps, width + eps, height + eps)});
    return s;
  }
};

/// Puts `total` [N] on the tip face (x = L) of the body's surface, spread by triangle area.
inline void loadTip(FemBody& body, double length, const Vec3& total) {
  DeformableSurface& s = body.surface();
  double area = 0.0;
  std::vector<std::pair<std::uint32_t, double>> tip;
  for (std::uint32_t t = 0; t < s.triangles().size(); ++t) {
    const auto& tri = s.triangles()[t];
    const Vec3& a = s.positions()[tri[0]];
    const Vec3& b = s.positions()[tri[1]];
    const Vec3& c = s.positions()[tri[2]];
    if (std::abs(a.x() - length) < 1e-9 && std::abs(b.x() - length) < 1e-9 &&
        std::abs(c.x() - length) < 1e-9) {
      const double at = 0.5 * (b - a).cross(c - a).norm();
      tip.emplace_back(t, at);
      area += at;
    }
  }
  for (const auto& [t, at] : tip) {
    const auto& tri = s.triangles()[t];
    const Vec3 centroid = (s.positions()[tri[0]] + s.positions()[tri[1]] + s.positions()[tri[2]]) / 3.0;
    s.addContactForce(t, centroid, total * (at / area));
  }
}

/// Mean z displacement of the nodes on the tip face x = L [m].
inline double tipZ(const FemBody& body, double length) {
  double sum = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < body.nodeCount(); ++i) {
    if (std::abs(body.nodePosition(i).x() - body.nodeDisplacement(i).x() - length) < 1e-9) {
      sum += body.nodeDisplacement(i).z();
      ++count;
    }
  }
  return sum / count;
}

}  // namespace demlink::core::fem_test
