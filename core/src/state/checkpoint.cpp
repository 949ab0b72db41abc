/// Checkpoint writing and reading: the file header, the order of the sections,
/// and the World's own counters and settings check (format in checkpoint.hpp and
/// docs/state.md). Each stateful object writes and reads its own section payload
/// (ParticleArrays, NeighbourList, PlaneWall, MeshBody, MeshNearList, FrameMotion,
/// ClumpBody, the components), checking what it reads.
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
/// Deformable bodies (section DEFM, written only when the scene has some, so files of
/// scenes without them are unchanged): per body its name, its own payload
/// (DeformableBody::save), its surface's mark and active flags and its near list.
///
/// Run-time inputs (section INPT, before END, written only when a client changed a
/// source's rate or state, a sink's state or region or a sensor's region): per such
/// component its name and its WorldComponent::saveInputs payload.
///
/// Mesh loads (section MLOD, after INPT, written only when the run accumulates them,
/// World::setContactOutput mesh_loads): per mesh its triangle count and every
/// TriangleLoad (current forces and the impulse and work integrals), so a restored run's
/// mesh frames continue the uninterrupted run's integrals. A world without mesh loads
/// skips the section; a file without it starts the integrals at zero.
///
/// Reading is in two phases: read and check the whole file into staging objects,
/// then replace the world's state, so a bad file leaves the world as it was.
/// Deformable bodies restore themselves; each is saved first, so a failure of a
/// later body or of the components puts every body back.
#include "demlink/core/state/checkpoint.hpp"

#include <cmath>
#include <fstream>
#include <istream>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "demlink/core/components/component_state.hpp"
#include "demlink/core/deformable/deformable_body.hpp"
#include "demlink/core/input_error.hpp"
#include "demlink/core/input_file.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/world.hpp"

namespace demlink::core {

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

/// World's own counters (section CLOK), read before anything is replaced.
struct Clock {
  std::uint64_t step_count = 0;
  std::uint64_t next_id = 0;
  RemovalTally removed;
  bool rebuild_pending = false;
  std::vector<std::uint32_t> pending;  ///< slot map since the last build (old slot -> current slot)
};

Clock readClock(StateReader& in) {
  Clock clock;
  clock.step_count = in.read<std::uint64_t>();
  clock.next_id = in.read<std::uint64_t>();
  clock.removed.count = in.read<std::uint64_t>();
  clock.removed.mass = in.read<double>();
  clock.rebuild_pending = in.read<std::uint8_t>() != 0;
  clock.pending = in.readVector<std::uint32_t>();
  in.requireEnd();
  return clock;
}

/// Rows and near-list slots are numbered as at the last build: the current slots
/// unless a slot mapping is pending; without a pending rebuild they are the particles.
void writeMeshLoads(StateWriter& out, const std::vector<std::vector<TriangleLoad>>& meshes) {
  out.write<std::uint64_t>(meshes.size());
  for (const std::vector<TriangleLoad>& loads : meshes) {
    out.write<std::uint64_t>(loads.size());
    for (const TriangleLoad& load : loads) {
      out.write(load.force);
      for (double value : {load.normal_force, load.tangential_force, load.normal_impulse, load.tangential_impulse,
                           load.archard_work, load.friction_work}) {
        out.write(value);
      }
    }
  }
}

std::vector<std::vector<TriangleLoad>> readMeshLoads(StateReader& in, const std::vector<MeshBody>& meshes) {
  readMatchingCount(in, "mesh", meshes.size());
  std::vector<std::vector<TriangleLoad>> loads(meshes.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    readMatchingCount(in, "triangle of mesh " + meshes[m].name(), meshes[m].triangles().size());
    loads[m].resize(meshes[m].triangles().size());
    for (TriangleLoad& load : loads[m]) {
      load.force = in.read<Vec3>();
      for (double* value : {&load.normal_force, &load.tangential_force, &load.normal_impulse,
                            &load.tangential_impulse, &load.archard_work, &load.friction_work}) {
        *value = in.read<double>();
      }
    }
  }
  in.requireEnd();
  return loads;
}

void checkRowsAgainstParticles(const StateReader& clockSection, const StateReader& nbrl, const Clock& clock,
                               std::size_t rows, std::size_t particles) {
  requireIndices(clockSection, clock.pending, particles, "pending slot map entry", true);
  if (!clock.pending.empty() && clock.pending.size() != rows) {
    clockSection.fail(std::to_string(clock.pending.size()), "pending slot map does not match the " +
                                                                std::to_string(rows) + " rows of the neighbour list");
  }
  if (clock.pending.empty() && rows > particles) {
    nbrl.fail(std::to_string(rows), "neighbour list has more rows than the " + std::to_string(particles) +
                                        " particles and no slot map");
  }
  if (!clock.rebuild_pending && (rows != particles || !clock.pending.empty())) {
    nbrl.fail(std::to_string(rows), "neighbour list rows differ from the " + std::to_string(particles) + " particles");
  }
}

}  // namespace

void World::saveCheckpoint(std::ostream& out) const {
  StateWriter w;
  writeHeader(w);
  w.section("SETT", [&] { writeSettings(w, settings_, state_); });
  w.section("MATL", [&] {
    w.write<std::uint64_t>(materials_.size());
    for (const Material& m : materials_) writeMaterial(w, m);
  });
  w.section("CLOK", [&] {
    w.write(state_.step_count);
    w.write(state_.next_particle_id);
    w.write(state_.removed_at_bounds.count);
    w.write(state_.removed_at_bounds.mass);
    w.write(static_cast<std::uint8_t>(rebuild_pending_));
    w.writeVector(pending_new_slot_of_old_);
  });
  w.section("PART", [&] { particles_.save(w); });
  w.section("NBRL", [&] { neighbours_.save(w); });
  w.section("PLAN", [&] {
    w.write<std::uint64_t>(planes_.size());
    for (const PlaneWall& wall : planes_) wall.save(w);
  });
  w.section("MESH", [&] {
    w.write<std::uint64_t>(meshes_.size());
    for (std::size_t m = 0; m < meshes_.size(); ++m) {
      meshes_[m].save(w);
      mesh_near_[m].save(w);
    }
  });
  w.section("ROOM", [&] {
    w.write(state_.bounds.lower);
    w.write(state_.bounds.upper);
    state_.frame.save(w);
    w.writeVector(mesh_colliding_);
  });
  w.section("CLMP", [&] {
    w.write<std::uint64_t>(clump_templates_.size());
    w.write(state_.next_clump_id);
    saveClumps(w, clumps_);
  });
  w.section("COMP", [&] { saveComponents(w, components_); });
  if (!deformables_.empty()) {
    w.section("DEFM", [&] {
      w.write<std::uint64_t>(deformables_.size());
      for (std::size_t d = 0; d < deformables_.size(); ++d) {
        w.writeString(deformables_[d]->name());
        deformables_[d]->save(w);
        deformables_[d]->surface().save(w);
        deformable_near_[d].save(w);
      }
    });
  }
  if (anyInputsChanged(components_)) w.section("INPT", [&] { saveComponentInputs(w, components_); });
  if (contact_output_.mesh_loads && !mesh_loads_.empty()) w.section("MLOD", [&] { writeMeshLoads(w, mesh_loads_); });
  w.section("END ", [] {});
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
  // Phase 1: every section into staging objects, each checked by its reader.
  StateReader file(bytes, source, "header");
  readHeader(file);
  checkSettings(file.section("SETT", "settings"), settings_, state_);
  checkMaterials(file.section("MATL", "materials"), materials_);
  StateReader clockSection = file.section("CLOK", "clock");
  const Clock clock = readClock(clockSection);

  StateReader partSection = file.section("PART", "particles");
  ParticleArrays particles;
  particles.restore(partSection);
  requireIndices(partSection, particles.material, materials_.size(), "particle material index");

  StateReader nbrl = file.section("NBRL", "neighbour_list");
  NeighbourList neighbours(neighbours_.skin());
  neighbours.restore(nbrl);
  const std::size_t rows = neighbours.rowCount();
  checkRowsAgainstParticles(clockSection, nbrl, clock, rows, particles.size());

  StateReader plan = file.section("PLAN", "planes");
  readMatchingCount(plan, "plane", planes_.size());
  std::vector<PlaneWall> planes = planes_;
  for (PlaneWall& wall : planes) wall.restore(plan, rows);
  plan.requireEnd();

  StateReader meshSection = file.section("MESH", "meshes");
  readMatchingCount(meshSection, "mesh", meshes_.size());
  std::vector<MeshBody::State> meshStates;
  std::vector<MeshNearList> meshNear(meshes_.size());
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    meshStates.push_back(meshes_[m].readState(meshSection));
    meshNear[m].restore(meshSection, rows, meshes_[m].triangles().size());
  }
  meshSection.requireEnd();

  StateReader room = file.section("ROOM", "room");
  DomainBounds bounds;
  bounds.lower = room.read<Vec3>();
  bounds.upper = room.read<Vec3>();
  FrameMotion frame;
  frame.restore(room);
  std::vector<char> colliding = room.readVector<char>();
  room.requireEnd();
  requireEqual(room, "colliding-flag count", static_cast<std::uint64_t>(colliding.size()),
               static_cast<std::uint64_t>(mesh_colliding_.size()));

  StateReader clmp = file.section("CLMP", "clumps");
  readMatchingCount(clmp, "clump template", clump_templates_.size());
  const auto nextClumpId = clmp.read<std::uint64_t>();
  std::vector<ClumpBody> clumps = restoreClumps(clmp, clump_templates_, particles.size());
  clmp.requireEnd();

  StateReader comp = file.section("COMP", "components");
  std::vector<StateReader> componentData = readComponentSections(comp, components_);
  std::optional<StateReader> defm;
  if (!deformables_.empty() || (!file.atEnd() && file.peekTag() == "DEFM")) {
    defm.emplace(file.section("DEFM", "deformable_bodies"));
  }
  // Run-time inputs (only in files of runs that changed some): checked names, loaded with
  // the components.
  std::vector<std::optional<StateReader>> inputs;
  if (!file.atEnd() && file.peekTag() == "INPT") {
    StateReader inpt = file.section("INPT", "inputs");
    inputs = readComponentInputs(inpt, components_);
  }
  std::vector<std::optional<StateReader>>* inputsOrNone = inputs.empty() ? nullptr : &inputs;
  std::optional<std::vector<std::vector<TriangleLoad>>> meshLoads;
  if (!file.atEnd() && file.peekTag() == "MLOD") {
    StateReader mlod = file.section("MLOD", "mesh_loads");
    meshLoads = readMeshLoads(mlod, meshes_);
  }
  (void)file.section("END ", "end");
  file.requireEnd();
  std::vector<MeshNearList> deformableNear(deformables_.size());
  std::vector<std::string> deformableBackup;
  if (defm) {
    readMatchingCount(*defm, "deformable body", deformables_.size());
    for (const auto& body : deformables_) {
      StateWriter backup;
      body->save(backup);
      body->surface().save(backup);
      deformableBackup.push_back(backup.bytes());
    }
    const auto putBack = [&](std::size_t count) {
      for (std::size_t d = 0; d < count; ++d) {
        StateReader saved(deformableBackup[d], source, "deformable_bodies");
        deformables_[d]->restore(saved);
        deformables_[d]->surface().restore(saved);
      }
    };
    std::size_t restored = 0;
    try {
      for (std::size_t d = 0; d < deformables_.size(); ++d) {
        requireEqual(*defm, "deformable body name", defm->readString(), deformables_[d]->name());
        ++restored;  // partly restored bodies are put back too
        deformables_[d]->restore(*defm);
        deformables_[d]->surface().restore(*defm);
        deformableNear[d].restore(*defm, rows, deformables_[d]->surface().triangles().size());
      }
      defm->requireEnd();
      // Components check their data while loading it and roll back together on failure.
      restoreComponents(components_, componentData, source, inputsOrNone);
    } catch (...) {
      putBack(restored);
      throw;
    }
  } else {
    restoreComponents(components_, componentData, source, inputsOrNone);
  }

  // Phase 2: everything read and checked: replace the state.
  particles_ = std::move(particles);
  for (const std::uint32_t material : particles_.material) coverMaterial(material);
  neighbours_ = std::move(neighbours);
  planes_ = std::move(planes);
  for (const PlaneWall& plane : planes_) coverMaterial(plane.spec.material);
  for (std::size_t m = 0; m < meshes_.size(); ++m) meshes_[m].restoreState(meshStates[m]);
  mesh_near_ = std::move(meshNear);
  deformable_near_ = std::move(deformableNear);
  state_.bounds = bounds;
  state_.setFrame(frame);
  selectStepStages();  // the restored frame may move where the scene's did not
  mesh_colliding_ = std::move(colliding);
  clumps_ = std::move(clumps);
  state_.next_clump_id = nextClumpId;
  state_.step_count = clock.step_count;
  state_.next_particle_id = clock.next_id;
  state_.removed_at_bounds = clock.removed;
  rebuild_pending_ = clock.rebuild_pending;
  pending_new_slot_of_old_ = clock.pending;
  partition_.plan(neighbours_.offsets(), neighbours_.partners());
  armRebuildGuard();
  if (contact_output_.mesh_loads) {
    mesh_loads_ = meshLoads ? std::move(*meshLoads) : std::vector<std::vector<TriangleLoad>>{};
  }
}

std::string readCheckpointBytes(const std::filesystem::path& path) {
  return readInputFile("checkpoint file", path);
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
  ParticleArrays p;
  p.restore(partSection);
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
