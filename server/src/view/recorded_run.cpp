/// A finished run as a ViewFeed (contract in recorded_run.hpp).
#include "demlink/server/view/recorded_run.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "demlink/core/base/input_error.hpp"
#include "json_text.hpp"

namespace demlink::server {
namespace {

/// The frame of `series` nearest in time to `time` (series written on the particles'
/// schedule match exactly).
const PvdFrame& nearestFrame(const std::vector<PvdFrame>& series, double time) {
  return *std::min_element(series.begin(), series.end(), [time](const PvdFrame& a, const PvdFrame& b) {
    return std::abs(a.time - time) < std::abs(b.time - time);
  });
}

float magnitude(const VtkColumn& column, std::size_t point) {
  double sum = 0.0;
  for (int c = 0; c < column.components; ++c) {
    const double v = column.values[point * static_cast<std::size_t>(column.components) + static_cast<std::size_t>(c)];
    sum += v * v;
  }
  return static_cast<float>(std::sqrt(sum));
}

}  // namespace

RecordedRun::RecordedRun(const std::filesystem::path& directory, const std::string& field) {
  const std::filesystem::path index = directory / "particles.pvd";
  if (!std::filesystem::is_regular_file(index)) {
    throw core::InputError(field, directory.string(), "no particles.pvd in it: not the output folder of a DEMLink run");
  }
  frames_ = readPvd(index);
  if (frames_.empty()) throw core::InputError(field, index.string(), "lists no frames");
  if (std::filesystem::is_regular_file(directory / "planes.vtp")) {
    surfaces_.push_back({"planes", {}, {{0.0, directory / "planes.vtp"}}, {}});
  }
  if (std::filesystem::is_regular_file(directory / "meshes.pvd")) {
    surfaces_.push_back({"meshes", {}, readPvd(directory / "meshes.pvd"), {}});
  }
  std::vector<std::filesystem::path> deformables;
  for (const auto& entry : std::filesystem::directory_iterator(directory)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("deformable_") && name.ends_with(".pvd")) deformables.push_back(entry.path());
  }
  std::sort(deformables.begin(), deformables.end());
  for (const std::filesystem::path& path : deformables) {
    std::vector<PvdFrame> series = readPvd(path);
    // FEM bodies write volumes (.vtu); the view draws surfaces only.
    if (!series.empty() && series.front().file.extension() == ".vtp") {
      surfaces_.push_back({path.stem().string().substr(11), {}, std::move(series), {}});
    }
  }
  std::erase_if(surfaces_, [](const SurfaceSeries& s) { return s.frames.empty(); });
  for (SurfaceSeries& surface : surfaces_) {
    PolyData first = readPolyData(surface.frames.front().file);
    surface.triangles = std::move(first.triangles);
    surface.springs = std::move(first.lines);  // a mass-spring body's springs; none elsewhere
  }

  std::uint64_t version = 0;
  const ViewSnapshot* first = snapshot(0, version);
  std::uint32_t materials = 0;
  for (const std::uint32_t m : first->material) materials = std::max(materials, m + 1);
  std::string json = R"({"kind":"scene","planes":[],"meshes":[],"surfaces":[)";
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    if (s > 0) json += ',';
    json += R"({"name":)";
    json += jsonString(surfaces_[s].name);
    json += R"(,"triangles":[)";
    for (std::size_t t = 0; t < surfaces_[s].triangles.size(); ++t) {
      const auto& triangle = surfaces_[s].triangles[t];
      json += fmt::format("{}{},{},{}", t == 0 ? "" : ",", triangle[0], triangle[1], triangle[2]);
    }
    json += R"(],"springs":[)";
    for (std::size_t k = 0; k < surfaces_[s].springs.size(); ++k) {
      json += fmt::format("{}{},{}", k == 0 ? "" : ",", surfaces_[s].springs[k][0], surfaces_[s].springs[k][1]);
    }
    json += "]}";
  }
  json += R"(],"regions":[],"materials":[)";
  for (std::uint32_t m = 0; m < materials; ++m) json += fmt::format("{}\"material {}\"", m == 0 ? "" : ",", m);
  scene_ = json + "]}";
}

double RecordedRun::frameTime(std::uint32_t index) const {
  return frames_[std::min<std::size_t>(index, frames_.size() - 1)].time;
}

const ViewSnapshot* RecordedRun::snapshot(std::uint32_t index, std::uint64_t& version) {
  index = std::min(index, static_cast<std::uint32_t>(frames_.size() - 1));
  if (!any_loaded_ || loaded_ != index) load(index);
  version = std::uint64_t{index} + 1;
  return &snapshot_;
}

void RecordedRun::load(std::uint32_t index) {
  const PvdFrame& frame = frames_[index];
  const PolyData particles = readPolyData(frame.file);
  const std::size_t n = particles.point_count;
  const auto column = [&](const std::string& name, int components) -> const VtkColumn& {
    const auto found = particles.point_data.find(name);
    if (found == particles.point_data.end() || found->second.components != components) {
      throw core::InputError("file", frame.file.string(), "no point data \"" + name + "\" of " +
                                                              std::to_string(components) + " component(s)");
    }
    return found->second;
  };
  const VtkColumn& radius = column("radius", 1);
  const VtkColumn& velocity = column("velocity", 3);
  const VtkColumn& force = column("force", 3);
  const VtkColumn& material = column("material", 1);
  const VtkColumn& id = column("id", 1);
  ViewSnapshot& s = snapshot_;
  s.position.resize(3 * n);
  s.radius.resize(n);
  s.speed.resize(n);
  s.force.resize(n);
  s.material.resize(n);
  s.id.resize(n);
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  std::array<float, 3> lower{kInfinity, kInfinity, kInfinity}, upper{-kInfinity, -kInfinity, -kInfinity};
  float largest = 0.0f;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const float x = static_cast<float>(particles.points[3 * i + axis]);
      s.position[3 * i + axis] = x;
      lower[axis] = std::min(lower[axis], x);
      upper[axis] = std::max(upper[axis], x);
    }
    s.radius[i] = static_cast<float>(radius.values[i]);
    largest = std::max(largest, s.radius[i]);
    s.speed[i] = magnitude(velocity, i);
    s.force[i] = magnitude(force, i);
    s.material[i] = static_cast<std::uint32_t>(material.integers[i]);
    s.id[i] = id.integers[i];
  }
  for (std::size_t axis = 0; axis < 3; ++axis) {
    s.box_lower[axis] = n > 0 ? lower[axis] - largest : 0.0f;
    s.box_upper[axis] = n > 0 ? upper[axis] + largest : 0.0f;
  }
  s.status = ViewStatus{};
  s.status.time = frame.time;
  s.meshes.clear();
  s.regions.clear();
  s.surfaces.resize(surfaces_.size());
  for (std::size_t k = 0; k < surfaces_.size(); ++k) {
    const PolyData surface = readPolyData(nearestFrame(surfaces_[k].frames, frame.time).file);
    s.surfaces[k].positions.assign(surface.points.begin(), surface.points.end());
    // A torn surface keeps its points and cells; its cell data "intact" (the springs', then
    // the triangles') says which still hold. Files without it: all of them.
    const std::size_t springs = surfaces_[k].springs.size(), triangles = surfaces_[k].triangles.size();
    const auto intact = surface.cell_data.find("intact");
    const bool flagged = intact != surface.cell_data.end() && intact->second.values.size() == springs + triangles;
    s.surfaces[k].spring_intact.assign(springs, 1);
    s.surfaces[k].triangle_active.assign(triangles, 1);
    for (std::size_t c = 0; flagged && c < springs + triangles; ++c) {
      const std::uint8_t holds = intact->second.values[c] != 0.0 ? 1 : 0;
      (c < springs ? s.surfaces[k].spring_intact[c] : s.surfaces[k].triangle_active[c - springs]) = holds;
    }
  }
  loaded_ = index;
  any_loaded_ = true;
}

}  // namespace demlink::server
