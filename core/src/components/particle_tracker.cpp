/// Tracker (contract in particle_tracker.hpp).
///
/// A sample scans the particle slots once and looks each id up in a small hash map of
/// the tracked ids, so its cost is O(N) per sample (not per step) whatever the number of
/// tracked particles.
#include "demlink/core/components/particle_tracker.hpp"

#include <limits>

#include "demlink/core/components/component_state.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/components/component_world.hpp"

namespace demlink::core {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void appendVector(std::vector<double>& row, const Vec3& v) { row.insert(row.end(), {v.x(), v.y(), v.z()}); }

/// A mesh name usable inside a CSV header (no separators or quotes).
std::string csvLabel(const std::string& name) {
  std::string label = name;
  for (char& c : label) {
    if (c == ',' || c == '"' || c == '\n' || c == '\r' || c == ' ') c = '_';
  }
  return label;
}

}  // namespace

ParticleTracker::ParticleTracker(std::string name, std::vector<std::uint64_t> particleIds,
                                 std::vector<std::size_t> meshIndices, SampleSchedule schedule,
                                 std::string fieldPrefix)
    : SampledComponent(std::move(name), schedule, std::move(fieldPrefix)) {
  const std::string& prefix = this->fieldPrefix();
  if (particleIds.empty() && meshIndices.empty()) {
    throw InputError(prefix + ".particle_ids", "[]", "a tracker needs at least one particle id or mesh body");
  }
  for (std::size_t k = 0; k < particleIds.size(); ++k) {
    const std::string field = prefix + ".particle_ids[" + std::to_string(k) + "]";
    if (particleIds[k] == 0) throw InputError(field, "0", "particle ids start at 1");
    if (!column_of_id_.emplace(particleIds[k], k).second) {
      throw InputError(field, std::to_string(particleIds[k]), "particle id listed twice");
    }
    particles_.push_back(TrackedParticle{.id = particleIds[k]});
  }
  for (std::size_t k = 0; k < meshIndices.size(); ++k) {
    for (std::size_t j = 0; j < k; ++j) {
      if (meshIndices[j] == meshIndices[k]) {
        throw InputError(prefix + ".mesh_bodies[" + std::to_string(k) + "]", std::to_string(meshIndices[k]),
                         "mesh body listed twice");
      }
    }
    meshes_.push_back(TrackedMesh{.index = meshIndices[k]});
  }
}

void ParticleTracker::initialize(ComponentWorld& world) {
  mesh_labels_.clear();
  for (std::size_t k = 0; k < meshes_.size(); ++k) {
    const std::size_t index = meshes_[k].index;
    if (index >= world.meshes().size()) {
      throw InputError(fieldPrefix() + ".mesh_bodies[" + std::to_string(k) + "]", std::to_string(index),
                       "no such mesh body (the scene has " + std::to_string(world.meshes().size()) + ")");
    }
    mesh_labels_.push_back(csvLabel(world.meshes()[index].name()));
  }
  resolveSchedule(world);
  sample(world);
}

void ParticleTracker::observe(const ComponentWorld& world) {
  if (sampleDue(world)) sample(world);
}

void ParticleTracker::sample(const ComponentWorld& world) {
  std::vector<bool> seen(particles_.size(), false);
  const ParticleArrays& p = world.particles();
  for (std::size_t i = 0; i < p.size() && !column_of_id_.empty(); ++i) {
    const auto column = column_of_id_.find(p.id[i]);
    if (column == column_of_id_.end()) continue;
    TrackedParticle& t = particles_[column->second];
    seen[column->second] = true;
    t.status = TrackedParticle::Status::Present;
    t.position = p.position[i];
    t.velocity = p.velocity[i];
    t.angular_velocity = p.angular_velocity[i];
    t.force = p.force[i];
  }
  std::vector<double> row{world.time()};
  for (std::size_t k = 0; k < particles_.size(); ++k) {
    TrackedParticle& t = particles_[k];
    if (!seen[k] && t.status == TrackedParticle::Status::Present) t.status = TrackedParticle::Status::Removed;
    row.push_back(static_cast<double>(static_cast<int>(t.status)));
    if (seen[k]) {
      appendVector(row, t.position);
      appendVector(row, t.velocity);
      appendVector(row, t.angular_velocity);
      appendVector(row, t.force);
    } else {
      row.insert(row.end(), 12, kNaN);
    }
  }
  for (TrackedMesh& m : meshes_) {
    const MeshBody& body = world.meshes()[m.index];
    m.position = body.position();
    m.orientation = body.orientation();
    m.linear_velocity = body.linearVelocity();
    m.angular_velocity = body.angularVelocity();
    m.force = body.force();
    m.torque = body.torque();
    appendVector(row, m.position);
    row.insert(row.end(), {m.orientation.w(), m.orientation.x(), m.orientation.y(), m.orientation.z()});
    appendVector(row, m.linear_velocity);
    appendVector(row, m.angular_velocity);
    appendVector(row, m.force);
    appendVector(row, m.torque);
  }
  publish(world, std::move(row));
}

void ParticleTracker::saveState(StateWriter& out) const {
  SampledComponent::saveState(out);
  const std::size_t section = out.beginSection("TRAK");
  out.write<std::uint64_t>(particles_.size());
  for (const TrackedParticle& t : particles_) {
    out.write(t.id);
    out.write(static_cast<std::int32_t>(t.status));
    out.write(t.position);
    out.write(t.velocity);
    out.write(t.angular_velocity);
    out.write(t.force);
  }
  out.write<std::uint64_t>(meshes_.size());
  for (const TrackedMesh& m : meshes_) {
    out.write<std::uint64_t>(m.index);
    out.write(m.position);
    out.write(m.orientation);
    out.write(m.linear_velocity);
    out.write(m.angular_velocity);
    out.write(m.force);
    out.write(m.torque);
  }
  out.endSection(section);
}

void ParticleTracker::loadState(StateReader& in) {
  SampledComponent::loadState(in);
  StateReader s = componentSection(in, "TRAK", "tracked");
  const auto particleCount = s.read<std::uint64_t>();
  if (particleCount != particles_.size()) {
    s.fail(std::to_string(particleCount), "tracked particle count differs from the scene's " +
                                              std::to_string(particles_.size()));
  }
  std::vector<TrackedParticle> particles = particles_;
  for (TrackedParticle& t : particles) {
    const auto id = s.read<std::uint64_t>();
    if (id != t.id) s.fail(std::to_string(id), "tracked particle id differs from the scene's " + std::to_string(t.id));
    const auto status = s.read<std::int32_t>();
    if (status < -1 || status > 1) s.fail(std::to_string(status), "tracked particle status must be -1, 0 or 1");
    t.status = static_cast<TrackedParticle::Status>(status);
    t.position = s.read<Vec3>();
    t.velocity = s.read<Vec3>();
    t.angular_velocity = s.read<Vec3>();
    t.force = s.read<Vec3>();
  }
  const auto meshCount = s.read<std::uint64_t>();
  if (meshCount != meshes_.size()) {
    s.fail(std::to_string(meshCount), "tracked mesh count differs from the scene's " + std::to_string(meshes_.size()));
  }
  std::vector<TrackedMesh> meshes = meshes_;
  for (TrackedMesh& m : meshes) {
    const auto index = s.read<std::uint64_t>();
    if (index != m.index) s.fail(std::to_string(index), "tracked mesh index differs from the scene's");
    m.position = s.read<Vec3>();
    m.orientation = s.read<Quat>();
    m.linear_velocity = s.read<Vec3>();
    m.angular_velocity = s.read<Vec3>();
    m.force = s.read<Vec3>();
    m.torque = s.read<Vec3>();
  }
  s.requireEnd();
  particles_ = std::move(particles);
  meshes_ = std::move(meshes);
}

std::vector<std::string> ParticleTracker::columns() const {
  std::vector<std::string> names{"time_s"};
  auto add = [&names](const std::string& label, std::initializer_list<const char*> suffixes) {
    for (const char* suffix : suffixes) {
      std::string column = label;
      column += '_';
      column += suffix;
      names.push_back(std::move(column));
    }
  };
  for (const TrackedParticle& t : particles_) {
    std::string label = std::to_string(t.id);
    label.insert(label.begin(), 'p');
    add(label, {"status", "x_m", "y_m", "z_m", "vx_m_s", "vy_m_s", "vz_m_s", "wx_rad_s", "wy_rad_s", "wz_rad_s",
                "fx_N", "fy_N", "fz_N"});
  }
  for (std::size_t k = 0; k < meshes_.size(); ++k) {
    std::string label = k < mesh_labels_.size() ? mesh_labels_[k] : std::to_string(meshes_[k].index);
    if (k >= mesh_labels_.size()) label.insert(0, "mesh");
    add(label, {"x_m", "y_m", "z_m", "qw", "qx", "qy", "qz", "vx_m_s", "vy_m_s", "vz_m_s", "wx_rad_s", "wy_rad_s",
                "wz_rad_s", "fx_N", "fy_N", "fz_N", "tx_N_m", "ty_N_m", "tz_N_m"});
  }
  return names;
}

}  // namespace demlink::core
