/// The world's checkpoint: the order of the sections, the world's own counters
/// and the settings check (format in checkpoint_file.hpp and
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
/// Parallel bonds (section BOND, after MLOD, written only when the scene declares bond
/// rules, so files of scenes without them are unchanged): BondSet::save, every bond by
/// its particles' ids with its force, moments and state; restored bonds find their slots
/// from the restored particles' ids.
///
/// Reading is in two phases: read and check the whole file into staging objects,
/// then replace the world's state, so a bad file leaves the world as it was.
/// Deformable bodies restore themselves; each is saved first, so a failure of a
/// later body or of the components puts every body back.
#include <istream>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "demlink/core/components/component_state.hpp"
#include "demlink/core/deformable/deformable_body.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/checkpoint_file.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/world.hpp"

namespace demlink::core {

namespace {

std::string quoted(const std::string& text) { return "\"" + text + "\""; }

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

/// Settings that change the trajectory must match; the thread count may differ (the
/// trajectory does not depend on it: the run continues in the same bits).
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
  writeCheckpointHeader(w);
  w.section("SETT", [&] { writeSettings(w, settings_, state_); });
  w.section("MATL", [&] {
    saveMaterials(w, materials_);
  });
  w.section("CLOK", [&] {
    w.write(state_.step_count);
    w.write(state_.next_particle_id);
    w.write(state_.removed_at_bounds.count);
    w.write(state_.removed_at_bounds.mass);
    w.write(static_cast<std::uint8_t>(neighbours_.rebuild_pending));
    w.writeVector(neighbours_.pending_new_slot_of_old);
  });
  w.section("PART", [&] { particles_.save(w); });
  w.section("NBRL", [&] { neighbours_.list.save(w); });
  w.section("PLAN", [&] {
    w.write<std::uint64_t>(walls_.planes.size());
    for (const PlaneWall& wall : walls_.planes) wall.save(w);
  });
  w.section("MESH", [&] {
    w.write<std::uint64_t>(walls_.meshes.size());
    for (std::size_t m = 0; m < walls_.meshes.size(); ++m) {
      walls_.meshes[m].save(w);
      walls_.mesh_near[m].save(w);
    }
  });
  w.section("FRAM", [&] {
    w.write(state_.bounds.lower);
    w.write(state_.bounds.upper);
    state_.frame.save(w);
    w.writeVector(walls_.mesh_colliding);
  });
  w.section("CLMP", [&] {
    w.write<std::uint64_t>(clumps_.templates.size());
    w.write(state_.next_clump_id);
    saveClumps(w, clumps_.bodies);
  });
  w.section("COMP", [&] { saveComponents(w, components_.all); });
  if (!deformables_.bodies.empty()) {
    w.section("DEFM", [&] {
      w.write<std::uint64_t>(deformables_.bodies.size());
      for (std::size_t d = 0; d < deformables_.bodies.size(); ++d) {
        w.writeString(deformables_.bodies[d]->name());
        deformables_.bodies[d]->save(w);
        deformables_.bodies[d]->surface().save(w);
        deformables_.near[d].save(w);
      }
    });
  }
  if (anyInputsChanged(components_.all)) w.section("INPT", [&] { saveComponentInputs(w, components_.all); });
  if (recorder_.settings.mesh_loads && !recorder_.mesh_loads.empty()) w.section("MLOD", [&] { writeMeshLoads(w, recorder_.mesh_loads); });
  if (bonds_.hasRules()) w.section("BOND", [&] { bonds_.save(w); });
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
  readCheckpointHeader(file);
  checkSettings(file.section("SETT", "settings"), settings_, state_);
  checkMaterials(file.section("MATL", "materials"), materials_);
  StateReader clockSection = file.section("CLOK", "clock");
  const Clock clock = readClock(clockSection);

  StateReader partSection = file.section("PART", "particles");
  ParticleArrays particles;
  particles.restore(partSection);
  requireIndices(partSection, particles.material, materials_.size(), "particle material index");

  StateReader nbrl = file.section("NBRL", "neighbour_list");
  NeighbourList neighbours(neighbours_.list.skin());
  neighbours.restore(nbrl);
  const std::size_t rows = neighbours.rowCount();
  checkRowsAgainstParticles(clockSection, nbrl, clock, rows, particles.size());

  StateReader plan = file.section("PLAN", "planes");
  readMatchingCount(plan, "plane", walls_.planes.size());
  std::vector<PlaneWall> planes = walls_.planes;
  for (PlaneWall& wall : planes) wall.restore(plan, rows);
  plan.requireEnd();

  StateReader meshSection = file.section("MESH", "meshes");
  readMatchingCount(meshSection, "mesh", walls_.meshes.size());
  std::vector<MeshBody::State> meshStates;
  std::vector<MeshNearList> meshNear(walls_.meshes.size());
  for (std::size_t m = 0; m < walls_.meshes.size(); ++m) {
    meshStates.push_back(walls_.meshes[m].readState(meshSection));
    meshNear[m].restore(meshSection, rows, walls_.meshes[m].triangles().size());
  }
  meshSection.requireEnd();

  StateReader frameSection = file.section("FRAM", "bounds_and_frame");
  DomainBounds bounds;
  bounds.lower = frameSection.read<Vec3>();
  bounds.upper = frameSection.read<Vec3>();
  FrameMotion frame;
  frame.restore(frameSection);
  std::vector<char> colliding = frameSection.readVector<char>();
  frameSection.requireEnd();
  requireEqual(frameSection, "colliding-flag count", static_cast<std::uint64_t>(colliding.size()),
               static_cast<std::uint64_t>(walls_.mesh_colliding.size()));

  StateReader clmp = file.section("CLMP", "clumps");
  readMatchingCount(clmp, "clump template", clumps_.templates.size());
  const auto nextClumpId = clmp.read<std::uint64_t>();
  std::vector<ClumpBody> clumps = restoreClumps(clmp, clumps_.templates, particles.size());
  clmp.requireEnd();

  StateReader comp = file.section("COMP", "components");
  std::vector<StateReader> componentData = readComponentSections(comp, components_.all);
  std::optional<StateReader> defm;
  if (!deformables_.bodies.empty() || (!file.atEnd() && file.peekTag() == "DEFM")) {
    defm.emplace(file.section("DEFM", "deformable_bodies"));
  }
  // Run-time inputs (only in files of runs that changed some): checked names, loaded with
  // the components.
  std::vector<std::optional<StateReader>> inputs;
  if (!file.atEnd() && file.peekTag() == "INPT") {
    StateReader inpt = file.section("INPT", "inputs");
    inputs = readComponentInputs(inpt, components_.all);
  }
  std::vector<std::optional<StateReader>>* inputsOrNone = inputs.empty() ? nullptr : &inputs;
  std::optional<std::vector<std::vector<TriangleLoad>>> meshLoads;
  if (!file.atEnd() && file.peekTag() == "MLOD") {
    StateReader mlod = file.section("MLOD", "mesh_loads");
    meshLoads = readMeshLoads(mlod, walls_.meshes);
  }
  BondSet bonds = bonds_;
  if (bonds_.hasRules() || (!file.atEnd() && file.peekTag() == "BOND")) {
    StateReader bond = file.section("BOND", "parallel_bonds");
    bonds.restore(bond, particles);
  }
  (void)file.section("END ", "end");
  file.requireEnd();
  std::vector<MeshNearList> deformableNear(deformables_.bodies.size());
  std::vector<std::string> deformableBackup;
  if (defm) {
    readMatchingCount(*defm, "deformable body", deformables_.bodies.size());
    for (const auto& body : deformables_.bodies) {
      StateWriter backup;
      body->save(backup);
      body->surface().save(backup);
      deformableBackup.push_back(backup.bytes());
    }
    const auto putBack = [&](std::size_t count) {
      for (std::size_t d = 0; d < count; ++d) {
        StateReader saved(deformableBackup[d], source, "deformable_bodies");
        deformables_.bodies[d]->restore(saved);
        deformables_.bodies[d]->surface().restore(saved);
      }
    };
    std::size_t restored = 0;
    try {
      for (std::size_t d = 0; d < deformables_.bodies.size(); ++d) {
        requireEqual(*defm, "deformable body name", defm->readString(), deformables_.bodies[d]->name());
        ++restored;  // partly restored bodies are put back too
        deformables_.bodies[d]->restore(*defm);
        deformables_.bodies[d]->surface().restore(*defm);
        deformableNear[d].restore(*defm, rows, deformables_.bodies[d]->surface().triangles().size());
      }
      defm->requireEnd();
      // Components check their data while loading it and roll back together on failure.
      restoreComponents(components_.all, componentData, source, inputsOrNone);
    } catch (...) {
      putBack(restored);
      throw;
    }
  } else {
    restoreComponents(components_.all, componentData, source, inputsOrNone);
  }

  // Phase 2: everything read and checked: replace the state.
  particles_ = std::move(particles);
  for (const std::uint32_t material : particles_.material) coverMaterial(material);
  neighbours_.list = std::move(neighbours);
  walls_.planes = std::move(planes);
  for (const PlaneWall& plane : walls_.planes) coverMaterial(plane.spec.material);
  for (std::size_t m = 0; m < walls_.meshes.size(); ++m) walls_.meshes[m].restoreState(meshStates[m]);
  walls_.mesh_near = std::move(meshNear);
  deformables_.near = std::move(deformableNear);
  state_.bounds = bounds;
  state_.setFrame(frame);
  selectStepStages();  // the restored frame may move where the scene's did not
  walls_.mesh_colliding = std::move(colliding);
  clumps_.bodies = std::move(clumps);
  bonds_ = std::move(bonds);
  state_.next_clump_id = nextClumpId;
  state_.step_count = clock.step_count;
  state_.next_particle_id = clock.next_id;
  state_.removed_at_bounds = clock.removed;
  neighbours_.rebuild_pending = clock.rebuild_pending;
  neighbours_.pending_new_slot_of_old = clock.pending;
  partition_.plan(neighbours_.list.offsets(), neighbours_.list.partners());
  armRebuildGuard();
  if (recorder_.settings.mesh_loads) {
    recorder_.mesh_loads = meshLoads ? std::move(*meshLoads) : std::vector<std::vector<TriangleLoad>>{};
  }
}

void writeCheckpointFile(const World& world, const std::filesystem::path& path) {
  std::ostringstream out;
  world.saveCheckpoint(out);
  writeCheckpointBytes(path, std::move(out).str());
}

void restoreCheckpointFile(World& world, const std::filesystem::path& path) {
  world.restoreCheckpoint(std::string_view(readCheckpointBytes(path)), path.string());
}

}  // namespace demlink::core
