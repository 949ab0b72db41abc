/// Checkpoint writing and reading: the one place that knows which World state the
/// next step reads (format in checkpoint.hpp and docs/state.md).
///
/// Why everything, bit for bit: a continued run must equal an uninterrupted one,
/// so besides positions and velocities the file holds the forces of the last
/// evaluation (Verlet's first half kick reads them), the neighbour list with its
/// tangential histories and reference positions (they decide when the next
/// rebuild happens), the build count (it decides when slots are re-sorted), the
/// plane and mesh near lists, the mesh poses and their displacement marks, the
/// pending slot map and the counters. Derived data (pair table, critical step,
/// force kernel, cell grid, thread partition) is recomputed from the scene.
///
/// Reading is in two phases: parse and check the whole file into a Restored
/// record, then replace the world's state, so a bad file leaves the world as it was.
#include "demlink/core/state/checkpoint.hpp"

#include <cmath>
#include <fstream>
#include <istream>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "demlink/core/input_error.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/world.hpp"

namespace demlink::core {

template <>
struct StateCodec<ReducedPair> {
  static constexpr std::size_t kBytes = 2 * sizeof(double);
  static void write(StateWriter& out, const ReducedPair& value) {
    out.write(value.radius);
    out.write(value.mass);
  }
  static void read(StateReader& in, ReducedPair& value) {
    value.radius = in.read<double>();
    value.mass = in.read<double>();
  }
};

namespace {

constexpr double kFloatProbe = -1.5;

std::string quoted(const std::string& text) { return "\"" + text + "\""; }

void writeHeader(StateWriter& out) {
  out.writeBytes(kCheckpointMagic, 8);
  out.write(kCheckpointVersion);
  out.write(kCheckpointByteOrderMark);
  out.write(static_cast<std::uint32_t>(sizeof(double)));
  out.write(kFloatProbe);
}

/// Checks magic, version, byte order and float format; leaves `in` at the first section.
void readHeader(StateReader& in) {
  char magic[8] = {};
  if (in.remaining() < sizeof magic) in.fail(std::to_string(in.remaining()) + " bytes", "too short for a checkpoint (empty or truncated file)");
  in.readBytes(magic, sizeof magic);
  if (std::string_view(magic, sizeof magic) != std::string_view(kCheckpointMagic, 8)) {
    in.fail("magic", "not a DEMLink checkpoint (the file does not start with \"DEMLCKPT\")");
  }
  const auto version = in.read<std::uint32_t>();
  if (version != kCheckpointVersion) {
    in.fail(std::to_string(version),
            "unsupported checkpoint format version (this engine reads version " +
                std::to_string(kCheckpointVersion) + ")");
  }
  const auto mark = in.read<std::uint32_t>();
  if (mark != kCheckpointByteOrderMark) in.fail("byte order", "written on a machine with another byte order");
  const auto doubleSize = in.read<std::uint32_t>();
  const auto probe = in.read<double>();
  if (doubleSize != sizeof(double) || probe != kFloatProbe) {
    in.fail("double format", "written with another floating-point format");
  }
}

/// Skips sections until the one tagged `tag` and returns it.
StateReader findSection(StateReader& file, std::string_view tag, const std::string& name) {
  while (!file.atEnd() && file.peekTag() != tag) file.skipSection();
  return file.section(tag, name);
}

template <class T>
void requireEqual(const StateReader& in, const std::string& what, const T& inFile, const T& inScene) {
  if (!(inFile == inScene)) {
    in.fail(what, "the checkpoint differs from the scene (restore into a world built from the same scene)");
  }
}

/// Gravity and the skin are the values in force (WorldState), as the format has
/// always recorded them.
void writeSettings(StateWriter& out, const SimulationSettings& s, const WorldState& state) {
  out.write(s.time_step);
  out.write(state.gravity);
  out.write(static_cast<std::uint32_t>(s.contact_model));
  out.write(static_cast<std::uint32_t>(s.integrator));
  out.write(state.neighbour_skin);
  out.write(s.max_impact_velocity);
  out.write(s.linear_normal_stiffness);
  out.write(static_cast<std::uint8_t>(s.bounds.has_value()));
  out.write(s.bounds ? s.bounds->lower : Vec3::Zero());
  out.write(s.bounds ? s.bounds->upper : Vec3::Zero());
  out.write(s.sort_every_builds);
  out.write(s.threads);
}

/// Settings that change the trajectory must match; the thread count may differ
/// (results are then equal to round-off only, as for any change of thread count).
void checkSettings(StateReader in, const SimulationSettings& s, const WorldState& state) {
  requireEqual(in, "time_step", in.read<double>(), s.time_step);
  requireEqual(in, "gravity", in.read<Vec3>(), state.gravity);
  requireEqual(in, "contact_model", in.read<std::uint32_t>(), static_cast<std::uint32_t>(s.contact_model));
  requireEqual(in, "integrator", in.read<std::uint32_t>(), static_cast<std::uint32_t>(s.integrator));
  requireEqual(in, "neighbour_skin", in.read<double>(), state.neighbour_skin);
  requireEqual(in, "max_impact_velocity", in.read<double>(), s.max_impact_velocity);
  requireEqual(in, "linear_normal_stiffness", in.read<double>(), s.linear_normal_stiffness);
  requireEqual(in, "bounds", in.read<std::uint8_t>(), static_cast<std::uint8_t>(s.bounds.has_value()));
  requireEqual(in, "bounds.lower", in.read<Vec3>(), s.bounds ? s.bounds->lower : Vec3::Zero());
  requireEqual(in, "bounds.upper", in.read<Vec3>(), s.bounds ? s.bounds->upper : Vec3::Zero());
  requireEqual(in, "sort_every_builds", in.read<std::uint32_t>(), s.sort_every_builds);
  (void)in.read<std::uint32_t>();
  in.requireEnd();
}

void writeMaterial(StateWriter& out, const Material& m) {
  out.writeString(m.name);
  for (double value : {m.density, m.youngs_modulus, m.poisson_ratio, m.restitution, m.sliding_friction,
                       m.rolling_friction}) {
    out.write(value);
  }
}

std::vector<std::string> readMaterialNames(StateReader in, std::vector<Material>* properties) {
  const auto count = in.read<std::uint64_t>();
  in.requireAvailable(count, sizeof(std::uint64_t) + 6 * sizeof(double), "material count");
  std::vector<std::string> names;
  for (std::uint64_t k = 0; k < count; ++k) {
    Material m;
    m.name = in.readString();
    m.density = in.read<double>();
    m.youngs_modulus = in.read<double>();
    m.poisson_ratio = in.read<double>();
    m.restitution = in.read<double>();
    m.sliding_friction = in.read<double>();
    m.rolling_friction = in.read<double>();
    names.push_back(m.name);
    if (properties) properties->push_back(m);
  }
  in.requireEnd();
  return names;
}

void checkMaterials(StateReader in, const std::vector<Material>& scene) {
  std::vector<Material> saved;
  const std::vector<std::string> names = readMaterialNames(in, &saved);
  requireEqual(in, "material count " + std::to_string(names.size()), names.size(), scene.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    const Material& a = saved[k];
    const Material& b = scene[k];
    requireEqual(in, "materials[" + std::to_string(k) + "].name " + quoted(a.name), a.name, b.name);
    const bool same = a.density == b.density && a.youngs_modulus == b.youngs_modulus &&
                      a.poisson_ratio == b.poisson_ratio && a.restitution == b.restitution &&
                      a.sliding_friction == b.sliding_friction && a.rolling_friction == b.rolling_friction;
    requireEqual(in, "materials[" + quoted(a.name) + "] properties", same, true);
  }
}

void writeParticles(StateWriter& out, const ParticleArrays& particles) {
  out.write<std::uint64_t>(particles.size());
  std::uint32_t columns = 0;
  particles.forEachColumn([&](const char*, const auto&) { ++columns; });
  out.write(columns);
  particles.forEachColumn([&](const char* name, const auto& column) {
    using T = typename std::decay_t<decltype(column)>::value_type;
    const std::size_t handle = out.beginSection("COL ");
    out.writeString(name);
    out.write(static_cast<std::uint32_t>(StateCodec<T>::kBytes));
    out.writeVector(column);
    out.endSection(handle);
  });
}

/// Reads the particle columns; every column of ParticleArrays must be present
/// with its element size and the common row count, and no unknown column.
ParticleArrays readParticles(StateReader in) {
  const auto rows = in.read<std::uint64_t>();
  const auto columns = in.read<std::uint32_t>();
  std::map<std::string, std::pair<std::uint32_t, StateReader>> found;
  for (std::uint32_t c = 0; c < columns; ++c) {
    StateReader column = in.section("COL ", "particles.column[" + std::to_string(c) + "]");
    std::string name = column.readString();
    const auto bytes = column.read<std::uint32_t>();
    found.emplace(name, std::pair{bytes, StateReader(column)});
  }
  in.requireEnd();
  ParticleArrays particles;
  std::size_t used = 0;
  particles.forEachColumn([&](const char* name, auto& column) {
    using T = typename std::decay_t<decltype(column)>::value_type;
    const auto it = found.find(name);
    if (it == found.end()) in.fail(name, "particle column missing from the checkpoint");
    StateReader& data = it->second.second;
    if (it->second.first != StateCodec<T>::kBytes) {
      data.fail(std::to_string(it->second.first), std::string("element size of column ") + name + " should be " +
                                                      std::to_string(StateCodec<T>::kBytes));
    }
    column = data.readVector<T>();
    data.requireEnd();
    if (column.size() != rows) {
      data.fail(std::to_string(column.size()), std::string("column ") + name + " length differs from the " +
                                                   std::to_string(rows) + " particles");
    }
    ++used;
  });
  if (used != found.size()) {
    for (const auto& entry : found) {
      bool known = false;
      particles.forEachColumn([&](const char* name, const auto&) { known = known || entry.first == name; });
      if (!known) in.fail(entry.first, "particle column unknown to this engine (written by a newer version?)");
    }
  }
  return particles;
}

/// Every index in `indices` is below `limit` (or kRemovedSlot when allowed).
void requireIndices(const StateReader& in, const std::vector<std::uint32_t>& indices, std::size_t limit,
                    const std::string& what, bool removedAllowed = false) {
  for (std::uint32_t index : indices) {
    if (index >= limit && !(removedAllowed && index == kRemovedSlot)) {
      in.fail(std::to_string(index), what + " out of range (limit " + std::to_string(limit) + ")");
    }
  }
}

/// offsets: starts at 0, non-decreasing, ends at `entries`.
void requireOffsets(const StateReader& in, const std::vector<std::uint32_t>& offsets, std::size_t entries,
                    const std::string& what) {
  if (offsets.empty() || offsets.front() != 0 || offsets.back() != entries) {
    in.fail(what, "row offsets inconsistent with " + std::to_string(entries) + " entries");
  }
  for (std::size_t k = 1; k < offsets.size(); ++k) {
    if (offsets[k] < offsets[k - 1]) in.fail(what, "row offsets decrease");
  }
}

template <class A, class B>
void requireSameLength(const StateReader& in, const A& a, const B& b, const std::string& what) {
  if (a.size() != b.size()) in.fail(std::to_string(a.size()) + " vs " + std::to_string(b.size()), what);
}

}  // namespace

void World::saveCheckpoint(std::ostream& out) const {
  StateWriter w;
  writeHeader(w);
  std::size_t s = w.beginSection("SETT");
  writeSettings(w, settings_, state_);
  w.endSection(s);

  s = w.beginSection("MATL");
  w.write<std::uint64_t>(materials_.size());
  for (const Material& m : materials_) writeMaterial(w, m);
  w.endSection(s);

  s = w.beginSection("CLOK");
  w.write(state_.step_count);
  w.write(state_.next_particle_id);
  w.write(state_.removed_at_bounds.count);
  w.write(state_.removed_at_bounds.mass);
  w.write(static_cast<std::uint8_t>(rebuild_pending_));
  w.writeVector(pending_new_slot_of_old_);
  w.endSection(s);

  s = w.beginSection("PART");
  writeParticles(w, particles_);
  w.endSection(s);

  s = w.beginSection("NBRL");
  w.write(neighbours_.skin_);
  w.write(neighbours_.builds_);
  w.writeVector(neighbours_.offsets_);
  w.writeVector(neighbours_.partners_);
  w.writeVector(neighbours_.history_);
  w.writeVector(neighbours_.reduced_);
  w.writeVector(neighbours_.position_at_build_);
  w.endSection(s);

  s = w.beginSection("PLAN");
  w.write<std::uint64_t>(planes_.size());
  for (const PlaneWall& wall : planes_) {
    w.writeString(wall.spec.name);
    w.writeVector(wall.near_slots);
    w.writeVector(wall.near_history);
    w.write(wall.force);
    w.write(wall.torque);
  }
  w.endSection(s);

  s = w.beginSection("MESH");
  w.write<std::uint64_t>(meshes_.size());
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const MeshBody& mesh = meshes_[m];
    w.writeString(mesh.name_);
    w.write<std::uint64_t>(mesh.triangles_.size());
    w.write(mesh.position_);
    w.write(mesh.orientation_);
    w.write(mesh.linearVelocity_);
    w.write(mesh.angularVelocity_);
    w.write(mesh.force_);
    w.write(mesh.torque_);
    w.write(mesh.markPosition_);
    w.write(mesh.markOrientation_);
    const MeshNearList& near = mesh_near_[m];
    w.writeVector(near.slots);
    w.writeVector(near.offsets);
    w.writeVector(near.triangles);
    w.writeVector(near.history);
  }
  w.endSection(s);

  s = w.beginSection("ROOM");
  w.write(state_.bounds.lower);
  w.write(state_.bounds.upper);
  w.write(state_.frame.linear_acceleration);
  w.write(state_.frame.angular_velocity);  // advanced by alpha dt every step
  w.write(state_.frame.angular_acceleration);
  w.write(state_.frame.origin);
  w.writeVector(mesh_colliding_);
  w.endSection(s);

  s = w.beginSection("CLMP");
  w.write<std::uint64_t>(clump_templates_.size());
  w.write(state_.next_clump_id);
  w.write<std::uint64_t>(clumps_.size());
  for (const ClumpBody& body : clumps_) {
    w.write(body.id);
    w.write(body.template_index);
    w.write(body.mass);
    w.write(body.inertia);
    w.write(body.position);
    w.write(body.velocity);
    w.write(body.orientation);
    w.write(body.angular_momentum);
    w.write(body.force);
    w.write(body.torque);
    w.writeVector(body.member_slots);
  }
  w.endSection(s);

  s = w.beginSection("COMP");
  w.write<std::uint64_t>(components_.size());
  for (const auto& component : components_) {
    w.writeString(component->name());
    w.writeString(component->kind());
    const std::size_t data = w.beginSection("DATA");
    component->saveState(w);
    w.endSection(data);
  }
  w.endSection(s);

  w.endSection(w.beginSection("END "));
  out.write(w.bytes().data(), static_cast<std::streamsize>(w.bytes().size()));
  if (!out) throw std::runtime_error("checkpoint: writing failed");
}

void World::restoreCheckpoint(std::istream& in, const std::string& source) {
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw InputError(source, "(unreadable)", "the checkpoint could not be read");
  const std::string text = bytes.str();
  restoreCheckpoint(std::string_view(text), source);
}

void World::restoreCheckpoint(std::string_view bytes, const std::string& source) {
  if (!initialized_) initialize();
  StateReader file(bytes, source, "header");
  readHeader(file);
  checkSettings(file.section("SETT", "settings"), settings_, state_);
  checkMaterials(file.section("MATL", "materials"), materials_);

  StateReader clock = file.section("CLOK", "clock");
  const auto stepCount = clock.read<std::uint64_t>();
  const auto nextId = clock.read<std::uint64_t>();
  RemovalTally removed;
  removed.count = clock.read<std::uint64_t>();
  removed.mass = clock.read<double>();
  const bool rebuildPending = clock.read<std::uint8_t>() != 0;
  std::vector<std::uint32_t> pending = clock.readVector<std::uint32_t>();
  clock.requireEnd();

  StateReader partSection = file.section("PART", "particles");
  ParticleArrays particles = readParticles(partSection);
  const std::size_t n = particles.size();
  requireIndices(partSection, particles.material, materials_.size(), "particle material index");
  requireIndices(clock, pending, n, "pending slot map entry", true);

  StateReader nbrl = file.section("NBRL", "neighbour_list");
  NeighbourList neighbours(nbrl.read<double>());
  requireEqual(nbrl, "neighbour skin", neighbours.skin_, neighbours_.skin_);
  neighbours.builds_ = nbrl.read<std::uint64_t>();
  neighbours.offsets_ = nbrl.readVector<std::uint32_t>();
  neighbours.partners_ = nbrl.readVector<std::uint32_t>();
  neighbours.history_ = nbrl.readVector<Vec3>();
  neighbours.reduced_ = nbrl.readVector<ReducedPair>();
  neighbours.position_at_build_ = nbrl.readVector<Vec3>();
  nbrl.requireEnd();
  // Rows and near-list slots are numbered as at the last build: the current
  // slots unless a slot mapping is pending.
  const std::size_t rows = neighbours.offsets_.empty() ? 0 : neighbours.offsets_.size() - 1;
  requireOffsets(nbrl, neighbours.offsets_, neighbours.partners_.size(), "neighbour offsets");
  requireIndices(nbrl, neighbours.partners_, rows, "neighbour partner");
  requireSameLength(nbrl, neighbours.history_, neighbours.partners_, "histories and partners differ in length");
  requireSameLength(nbrl, neighbours.reduced_, neighbours.partners_, "pair data and partners differ in length");
  if (!pending.empty() && pending.size() != rows) {
    clock.fail(std::to_string(pending.size()), "pending slot map does not match the " + std::to_string(rows) +
                                                   " rows of the neighbour list");
  }
  if (pending.empty() && rows > n) {
    nbrl.fail(std::to_string(rows), "neighbour list has more rows than the " + std::to_string(n) +
                                        " particles and no slot map");
  }
  if (!rebuildPending && (rows != n || !pending.empty())) {
    nbrl.fail(std::to_string(rows), "neighbour list rows differ from the " + std::to_string(n) + " particles");
  }

  StateReader plan = file.section("PLAN", "planes");
  const auto planeCount = plan.read<std::uint64_t>();
  requireEqual(plan, "plane count " + std::to_string(planeCount), planeCount,
               static_cast<std::uint64_t>(planes_.size()));
  std::vector<PlaneWall> planes = planes_;
  for (PlaneWall& wall : planes) {
    const std::string name = plan.readString();
    requireEqual(plan, "plane name " + quoted(name), name, wall.spec.name);
    wall.near_slots = plan.readVector<std::uint32_t>();
    wall.near_history = plan.readVector<Vec3>();
    wall.force = plan.read<Vec3>();
    wall.torque = plan.read<Vec3>();
    requireIndices(plan, wall.near_slots, rows, "plane near-list slot");
    requireSameLength(plan, wall.near_history, wall.near_slots, "plane histories and slots differ in length");
  }
  plan.requireEnd();

  StateReader meshSection = file.section("MESH", "meshes");
  const auto meshCount = meshSection.read<std::uint64_t>();
  requireEqual(meshSection, "mesh count " + std::to_string(meshCount), meshCount,
               static_cast<std::uint64_t>(meshes_.size()));
  struct MeshState {
    Vec3 position, linear, angular, force, torque, mark_position;
    Quat orientation, mark_orientation;
    MeshNearList near;
  };
  std::vector<MeshState> meshStates(meshes_.size());
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    MeshState& state = meshStates[m];
    const std::string name = meshSection.readString();
    requireEqual(meshSection, "mesh name " + quoted(name), name, meshes_[m].name_);
    const auto triangles = meshSection.read<std::uint64_t>();
    requireEqual(meshSection, "triangle count " + std::to_string(triangles) + " of mesh " + quoted(name),
                 triangles, static_cast<std::uint64_t>(meshes_[m].triangles_.size()));
    state.position = meshSection.read<Vec3>();
    state.orientation = meshSection.read<Quat>();
    state.linear = meshSection.read<Vec3>();
    state.angular = meshSection.read<Vec3>();
    state.force = meshSection.read<Vec3>();
    state.torque = meshSection.read<Vec3>();
    state.mark_position = meshSection.read<Vec3>();
    state.mark_orientation = meshSection.read<Quat>();
    state.near.slots = meshSection.readVector<std::uint32_t>();
    state.near.offsets = meshSection.readVector<std::uint32_t>();
    state.near.triangles = meshSection.readVector<std::uint32_t>();
    state.near.history = meshSection.readVector<Vec3>();
    requireIndices(meshSection, state.near.slots, rows, "mesh near-list slot");
    requireIndices(meshSection, state.near.triangles, triangles, "mesh near-list triangle");
    requireOffsets(meshSection, state.near.offsets, state.near.triangles.size(), "mesh near-list offsets");
    if (state.near.offsets.size() != state.near.slots.size() + 1) {
      meshSection.fail(std::to_string(state.near.offsets.size()), "mesh near-list offsets do not match its slots");
    }
    requireSameLength(meshSection, state.near.history, state.near.triangles,
                      "mesh histories and candidates differ in length");
    const double qNorm = state.orientation.norm();
    if (!(std::abs(qNorm - 1.0) < 1.0e-9)) meshSection.fail("orientation", "not a unit quaternion");
  }
  meshSection.requireEnd();

  StateReader room = file.section("ROOM", "room");
  DomainBounds bounds;
  bounds.lower = room.read<Vec3>();
  bounds.upper = room.read<Vec3>();
  FrameMotion frame;
  frame.linear_acceleration = room.read<Vec3>();
  frame.angular_velocity = room.read<Vec3>();
  frame.angular_acceleration = room.read<Vec3>();
  frame.origin = room.read<Vec3>();
  std::vector<char> colliding = room.readVector<char>();
  room.requireEnd();
  requireEqual(room, "colliding-flag count", static_cast<std::uint64_t>(colliding.size()),
               static_cast<std::uint64_t>(mesh_colliding_.size()));

  StateReader clmp = file.section("CLMP", "clumps");
  requireEqual(clmp, "clump template count", clmp.read<std::uint64_t>(),
               static_cast<std::uint64_t>(clump_templates_.size()));
  const auto nextClumpId = clmp.read<std::uint64_t>();
  const auto clumpCount = clmp.read<std::uint64_t>();
  // Each body needs well over 64 bytes: a corrupt count cannot allocate much.
  if (clumpCount > clmp.remaining() / 64) clmp.fail(std::to_string(clumpCount), "clump count exceeds the section");
  std::vector<ClumpBody> clumps(clumpCount);
  for (ClumpBody& body : clumps) {
    body.id = clmp.read<std::uint64_t>();
    body.template_index = clmp.read<std::uint32_t>();
    body.mass = clmp.read<double>();
    body.inertia = clmp.read<Vec3>();
    body.position = clmp.read<Vec3>();
    body.velocity = clmp.read<Vec3>();
    body.orientation = clmp.read<Quat>();
    body.angular_momentum = clmp.read<Vec3>();
    body.force = clmp.read<Vec3>();
    body.torque = clmp.read<Vec3>();
    body.member_slots = clmp.readVector<std::uint32_t>();
    if (body.template_index >= clump_templates_.size()) {
      clmp.fail(std::to_string(body.template_index), "clump template index out of range");
    }
    requireEqual(clmp, "member count of clump " + std::to_string(body.id),
                 static_cast<std::uint64_t>(body.member_slots.size()),
                 static_cast<std::uint64_t>(clump_templates_[body.template_index].spheres().size()));
    requireIndices(clmp, body.member_slots, n, "clump member slot");
  }
  clmp.requireEnd();

  StateReader comp = file.section("COMP", "components");
  const auto componentCount = comp.read<std::uint64_t>();
  requireEqual(comp, "component count " + std::to_string(componentCount), componentCount,
               static_cast<std::uint64_t>(components_.size()));
  std::vector<StateReader> componentData;
  for (const auto& component : components_) {
    const std::string name = comp.readString();
    const std::string kind = comp.readString();
    requireEqual(comp, "component " + quoted(name), name, component->name());
    requireEqual(comp, "kind " + quoted(kind) + " of component " + quoted(name), kind,
                 std::string(component->kind()));
    componentData.push_back(comp.section("DATA", "components." + name));
  }
  comp.requireEnd();
  (void)file.section("END ", "end");
  file.requireEnd();

  // Components check their own data while loading it; if one refuses, every
  // component gets its previous state back, so a failed restore changes nothing.
  std::vector<std::string> previousStates;
  for (const auto& component : components_) {
    StateWriter backup;
    component->saveState(backup);
    previousStates.push_back(backup.bytes());
  }
  try {
    for (std::size_t k = 0; k < components_.size(); ++k) {
      components_[k]->loadState(componentData[k]);
      componentData[k].requireEnd();
    }
  } catch (...) {
    for (std::size_t k = 0; k < components_.size(); ++k) {
      StateReader backup(previousStates[k], source, "components." + components_[k]->name());
      components_[k]->loadState(backup);
    }
    throw;
  }

  // Everything read and checked: replace the state.
  particles_ = std::move(particles);
  neighbours_ = std::move(neighbours);
  planes_ = std::move(planes);
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    MeshBody& mesh = meshes_[m];
    const MeshState& state = meshStates[m];
    mesh.position_ = state.position;
    mesh.orientation_ = state.orientation;
    mesh.linearVelocity_ = state.linear;
    mesh.angularVelocity_ = state.angular;
    mesh.force_ = state.force;
    mesh.torque_ = state.torque;
    mesh.markPosition_ = state.mark_position;
    mesh.markOrientation_ = state.mark_orientation;
    mesh.updateWorldGeometry();
    mesh_near_[m] = state.near;
  }
  state_.bounds = bounds;
  state_.setFrame(frame);
  selectStepStages();  // the restored frame may move where the scene's did not
  mesh_colliding_ = std::move(colliding);
  clumps_ = std::move(clumps);
  state_.next_clump_id = nextClumpId;
  state_.step_count = stepCount;
  state_.next_particle_id = nextId;
  state_.removed_at_bounds = removed;
  rebuild_pending_ = rebuildPending;
  pending_new_slot_of_old_ = std::move(pending);
  partition_.plan(neighbours_.offsets(), settings_.threads);
}

std::string readCheckpointBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "(unreadable)", "cannot open the checkpoint file");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw InputError(path.string(), "(unreadable)", "cannot read the checkpoint file");
  return bytes.str();
}

void writeCheckpointFile(const World& world, const std::filesystem::path& path) {
  std::filesystem::path temporary = path;
  temporary += ".partial";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write checkpoint " + temporary.string());
    world.saveCheckpoint(out);
    out.flush();
    if (!out) throw std::runtime_error("cannot write checkpoint " + temporary.string());
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) throw std::runtime_error("cannot rename " + temporary.string() + " to " + path.string() + ": " + ec.message());
}

void restoreCheckpointFile(World& world, const std::filesystem::path& path) {
  world.restoreCheckpoint(std::string_view(readCheckpointBytes(path)), path.string());
}

CheckpointParticles readCheckpointParticles(const std::filesystem::path& path) {
  const std::string bytes = readCheckpointBytes(path);
  StateReader file(bytes, path.string(), "header");
  readHeader(file);
  CheckpointParticles out;
  StateReader settings = findSection(file, "SETT", "settings");
  const double dt = settings.read<double>();
  out.material_names = readMaterialNames(findSection(file, "MATL", "materials"), nullptr);
  StateReader clock = findSection(file, "CLOK", "clock");
  out.time = static_cast<double>(clock.read<std::uint64_t>()) * dt;
  StateReader partSection = findSection(file, "PART", "particles");
  const ParticleArrays p = readParticles(partSection);
  requireIndices(partSection, p.material, out.material_names.size(), "particle material index");
  out.particles.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    ParticleSpec& spec = out.particles[i];
    spec.position = p.position[i];
    spec.velocity = p.velocity[i];
    spec.angular_velocity = p.angular_velocity[i];
    spec.radius = p.radius[i];
    spec.material = p.material[i];
  }
  out.ids = p.id;
  return out;
}

}  // namespace demlink::core
