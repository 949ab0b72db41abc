/// Output files of a headless run (layout in headless_runner.hpp).
///
/// Planes are infinite; for ParaView each is drawn as a square of side
/// L = max extent of the scene box (the domain bounds if set, else the bounding
/// box of particle centres and plane points), centred on the projection of the
/// box centre c onto the plane: p = c - ((c - point) . n) n, spanned by a unit
/// tangent t1 (any, orthogonal to n) and t2 = n x t1, corners ordered
/// counter-clockwise about n so the quad's normal is the wall's normal.
#include "demlink/server/run/frame_series.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <system_error>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/output/csv_table.hpp"

namespace demlink::server {

FrameStats frameStats(const core::World& world) {
  const core::ParticleArrays& particles = world.particles();
  FrameStats stats;
  stats.time = world.time();
  stats.particles = particles.size();
  stats.kinetic_energy = world.kineticEnergy();
  stats.neighbour_builds = world.neighbourList().buildCount();
  if (particles.size() == 0) {
    stats.mean_z = stats.max_z = std::numeric_limits<double>::quiet_NaN();
    return stats;
  }
  double sum = 0.0;
  double highest = -std::numeric_limits<double>::infinity();
  for (const core::Vec3& x : particles.position) {
    sum += x.z();
    highest = std::max(highest, x.z());
  }
  stats.mean_z = sum / static_cast<double>(particles.size());
  stats.max_z = highest;
  return stats;
}

FrameSeries::FrameSeries(std::filesystem::path directory, const std::string& field)
    : directory_(std::move(directory)) {
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec || !std::filesystem::is_directory(directory_)) {
    throw core::InputError(field, "\"" + directory_.string() + "\"",
                           "cannot create the output directory" + (ec ? ": " + ec.message() : std::string()));
  }
  const std::filesystem::path csv = directory_ / "summary.csv";
  summary_.open(csv, std::ios::trunc);
  if (!summary_) throw core::InputError(field, "\"" + directory_.string() + "\"", "cannot write " + csv.string());
  summary_ << "time_s,particles,kinetic_energy_J,mean_z_m,max_z_m,neighbour_builds,wall_s\n";
  summary_.flush();
}

void FrameSeries::writePlanes(const core::World& world) {
  const std::vector<core::PlaneWall>& planes = world.planes();
  if (planes.empty()) return;
  core::Vec3 lower = core::Vec3::Constant(std::numeric_limits<double>::infinity());
  core::Vec3 upper = -lower;
  if (world.settings().bounds) {
    lower = world.settings().bounds->lower;
    upper = world.settings().bounds->upper;
  } else {
    for (const core::Vec3& x : world.particles().position) {
      lower = lower.cwiseMin(x);
      upper = upper.cwiseMax(x);
    }
    for (const core::PlaneWall& wall : planes) {
      lower = lower.cwiseMin(wall.spec.point);
      upper = upper.cwiseMax(wall.spec.point);
    }
  }
  const core::Vec3 centre = 0.5 * (lower + upper);
  const double half = 0.5 * std::max((upper - lower).maxCoeff(), 1.0e-3);  // [m]

  std::vector<core::Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (const core::PlaneWall& wall : planes) {
    const core::Vec3& n = wall.spec.normal;
    const core::Vec3 p = centre - (centre - wall.spec.point).dot(n) * n;
    const core::Vec3 t1 = n.unitOrthogonal();
    const core::Vec3 t2 = n.cross(t1);
    const auto first = static_cast<std::uint32_t>(vertices.size());
    vertices.push_back(p - half * t1 - half * t2);
    vertices.push_back(p + half * t1 - half * t2);
    vertices.push_back(p + half * t1 + half * t2);
    vertices.push_back(p - half * t1 + half * t2);
    triangles.push_back({first, first + 1, first + 2});
    triangles.push_back({first, first + 2, first + 3});
  }
  core::writeMeshVtp((directory_ / "planes.vtp").string(), vertices, triangles);
}

FrameStats FrameSeries::writeFrame(const core::World& world, double wallSeconds) {
  FrameStats stats = frameStats(world);
  stats.wall_seconds = wallSeconds;
  const std::string file = fmt::format("particles_{:06}.vtp", entries_.size());
  core::writeParticlesVtp((directory_ / file).string(), world.particles());
  entries_.push_back({stats.time, file});
  core::writePvd((directory_ / "particles.pvd").string(), entries_);
  if (!world.meshes().empty()) writeMeshes(world, stats.time);
  if (world.bonds().hasRules()) writeBonds(world, stats.time);
  // mean_z and max_z of a frame without particles do not exist: empty cells (core::csvNumber).
  summary_ << fmt::format("{},{},{},{},{},{},{:.3f}\n", core::csvNumber(stats.time), stats.particles,
                          core::csvNumber(stats.kinetic_energy), core::csvNumber(stats.mean_z),
                          core::csvNumber(stats.max_z), stats.neighbour_builds, stats.wall_seconds);
  summary_.flush();
  if (!summary_) throw std::runtime_error("cannot write " + (directory_ / "summary.csv").string());
  return stats;
}

void FrameSeries::writeBonds(const core::World& world, double time) {
  const std::string file = fmt::format("bonds_{:06}.vtp", bond_entries_.size());
  core::writeBondsVtp((directory_ / file).string(), world.bonds(), world.particles());
  bond_entries_.push_back({time, file});
  core::writePvd((directory_ / "bonds.pvd").string(), bond_entries_);
}

void FrameSeries::writeMeshes(const core::World& world, double time) {
  // All meshes of the frame in one file, so ParaView shows them as one series.
  std::vector<core::Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  const bool loads = world.contactOutput().mesh_loads;
  std::vector<core::TriangleLoad> triangleLoads;
  for (std::size_t m = 0; m < world.meshes().size(); ++m) {
    const core::MeshBody& mesh = world.meshes()[m];
    const auto base = static_cast<std::uint32_t>(vertices.size());
    vertices.insert(vertices.end(), mesh.worldVertices().begin(), mesh.worldVertices().end());
    for (const auto& t : mesh.triangles()) triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    if (!loads) continue;
    const std::span<const core::TriangleLoad> meshLoads = world.meshLoads(m);
    triangleLoads.insert(triangleLoads.end(), meshLoads.begin(), meshLoads.end());
    triangleLoads.resize(triangles.size());  // no evaluation yet: zeros
  }
  const std::string file = fmt::format("meshes_{:06}.vtp", mesh_entries_.size());
  if (loads) {
    core::writeMeshLoadsVtp((directory_ / file).string(), vertices, triangles, triangleLoads);
  } else {
    core::writeMeshVtp((directory_ / file).string(), vertices, triangles);
  }
  mesh_entries_.push_back({time, file});
  core::writePvd((directory_ / "meshes.pvd").string(), mesh_entries_);
}

}  // namespace demlink::server
