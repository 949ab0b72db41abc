/// Scene compiler: protobuf declarations -> core::World + RunOptions.
///
/// Four passes over the declarations, so that errors come out in a useful order
/// and the scene's order does not matter for references:
///   1. structure: every component has a unique non-empty name and a kind, and
///      there is exactly one simulation_box (its settings build the World);
///   2. materials, in declaration order (indices follow it);
///   3. planes, particle sets and meshes, in declaration order;
///   4. deformable bodies (translate_deformables), which may ride on meshes;
///   5. sinks, sensors and trackers (translate_sensors), which refer to meshes and
///      deformable bodies by name;
///   6. parallel bonds (translate_bonds), whose rules see every particle set.
/// Every field is checked here or by the core validators with a field path
/// "components[i].<kind>.<field>", so a user can find it in the scene file.
#include "demlink/server/scene/scene_translator.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <map>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "demlink/core/contact/contact_law_registry.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/core/base/names.hpp"
#include "demlink/core/parallel/thread_pool.hpp"
#include "demlink/server/scene/fidelity_preset.hpp"
#include "demlink/server/scene/input_limits.hpp"
#include "demlink/server/scene/particle_file_reader.hpp"
#include "demlink/server/scene/particle_lattice.hpp"
#include "demlink/server/scene/proto_convert.hpp"
#include "demlink/server/scene/translate_materials.hpp"
#include "demlink/server/scene/translate_bonds.hpp"
#include "demlink/server/scene/translate_sensors.hpp"
#include "demlink/server/scene/translate_sources.hpp"
#include "demlink/server/scene/translate_state.hpp"
#include "demlink/server/scene/translate_facets.hpp"
#include "demlink/server/scene/translate_frame.hpp"
#include "demlink/server/scene/translate_clumps.hpp"
#include "demlink/server/scene/translate_deformables.hpp"
#include "demlink/server/scene/translate_rigid_body.hpp"

namespace demlink::server {
namespace {

using core::InputError;
using MaterialNames = std::map<std::string, std::uint32_t>;

std::string quoted(const std::string& text) { return core::quotedLogText(text); }

std::uint32_t resolveMaterial(const MaterialNames& materials, const std::string& name, const std::string& field) {
  if (name.empty()) throw InputError(field, "\"\"", "a material name is required");
  const auto it = materials.find(name);
  if (it != materials.end()) return it->second;
  std::string declared;
  for (const auto& entry : materials) declared += (declared.empty() ? "" : ", ") + entry.first;
  throw InputError(field, quoted(name), "unknown material (declared: " + (declared.empty() ? "none" : declared) + ")");
}

/// Pass 1. Returns the index of the single simulation_box.
int checkStructure(const v1::Scene& scene) {
  std::map<std::string, int> firstUse;
  std::vector<int> boxes;
  for (int i = 0; i < scene.components_size(); ++i) {
    const v1::ComponentDeclaration& component = scene.components(i);
    const std::string path = componentPath(i);
    if (component.name().empty()) throw InputError(path + ".name", "\"\"", "every component needs a name");
    core::requireValidName(path + ".name", component.name());
    const auto [it, inserted] = firstUse.emplace(component.name(), i);
    if (!inserted) {
      throw InputError(path + ".name", quoted(component.name()),
                       "component name already used by " + componentPath(it->second));
    }
    if (component.kind_case() == v1::ComponentDeclaration::KIND_NOT_SET) {
      throw InputError(path, quoted(component.name()),
                       "declares no kind (one of simulation_box, material, plane, mesh_body, particle_lattice, "
                       "particle_file, particle_system, single_particle, particle_source, pit_generator, "
                       "particle_sink, region_sensor, flow_sensor, tracker, clump_template, facet_body, material_pair, "
                       "rigid_body, particle_view, mass_spring_body, fem_body, parallel_bonds)");
    }
    if (component.has_simulation_box()) boxes.push_back(i);
  }
  if (boxes.size() != 1) {
    std::string where;
    for (int i : boxes) where += (where.empty() ? " (" : ", ") + componentPath(i);
    if (!where.empty()) where += ")";
    throw InputError("components", std::to_string(boxes.size()) + " simulation_box components",
                     "a scene needs exactly one simulation_box, found " + std::to_string(boxes.size()) + where);
  }
  return boxes.front();
}

/// The scene's contact model is the registry's law of the same name (HERTZ_MINDLIN ->
/// "hertz_mindlin", contact_law_registry.hpp), so a new law needs its registry entry and its
/// enum value, and no switch here; unspecified is Hertz-Mindlin.
core::ContactModel contactModelOf(const v1::SimulationBox& box, const std::string& prefix) {
  if (box.contact_model() == v1::SimulationBox::CONTACT_MODEL_UNSPECIFIED) return core::ContactModel::HertzMindlin;
  std::string name = v1::SimulationBox::ContactModel_Name(box.contact_model());
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (const std::optional<core::ContactModel> model = core::contactModelNamed(name)) return *model;
  throw InputError(prefix + ".contact_model", std::to_string(box.contact_model()), "unknown contact model");
}

core::SimulationSettings toSettings(const v1::SimulationBox& box, const std::string& prefix,
                                    const core::CoarseGraining& coarse, FidelityChoice& fidelity) {
  core::SimulationSettings settings;
  if (box.has_time_step()) settings.time_step = box.time_step();
  if (box.has_gravity()) settings.gravity = toVec3(box.gravity());
  settings.contact_model = contactModelOf(box, prefix);
  switch (box.integrator()) {
    case v1::SimulationBox::INTEGRATOR_UNSPECIFIED:
    case v1::SimulationBox::VELOCITY_VERLET: settings.integrator = core::IntegratorKind::VelocityVerlet; break;
    case v1::SimulationBox::EXPLICIT_EULER: settings.integrator = core::IntegratorKind::ExplicitEuler; break;
    default: throw InputError(prefix + ".integrator", std::to_string(box.integrator()), "unknown integrator");
  }
  settings.neighbour_skin = box.neighbour_skin();
  if (box.has_max_impact_velocity()) settings.max_impact_velocity = box.max_impact_velocity();
  // k_n ~ E R keeps delta / R; a Hertz-derived stiffness (0) follows the radii by itself.
  settings.linear_normal_stiffness = coarse.linearStiffness(box.linear_normal_stiffness());
  if (box.has_restitution_tolerance()) settings.restitution_tolerance = box.restitution_tolerance();
  settings.allow_unsafe_time_step = box.allow_unsafe_time_step();
  settings.portable_kernel = box.portable_kernel();
  if (box.has_threads()) {
    if (box.threads() == 0) {
      const core::AutoThreadChoice choice = core::chooseAutoThreads();
      settings.threads = std::min(choice.threads, core::maxThreads());
      settings.threads_choice = choice.reason;
    } else {
      settings.threads = box.threads();
    }
  }
  if (box.has_bounds()) {
    const v1::SimulationBox::Bounds& bounds = box.bounds();
    if (!bounds.has_lower()) throw InputError(prefix + ".bounds.lower", "(missing)", "required when bounds is given");
    if (!bounds.has_upper()) throw InputError(prefix + ".bounds.upper", "(missing)", "required when bounds is given");
    settings.bounds = core::DomainBounds{toVec3(bounds.lower()), toVec3(bounds.upper())};
  }
  translateFrame(box, prefix, settings);
  if (box.has_watchdog()) {
    const v1::SimulationBox::Watchdog& w = box.watchdog();
    core::WatchdogSettings& out = settings.watchdog;
    auto policy = [&](v1::SimulationBox::Watchdog::Policy p, core::GuardPolicy fallback, const std::string& field) {
      switch (p) {
        case v1::SimulationBox::Watchdog::POLICY_UNSPECIFIED: return fallback;
        case v1::SimulationBox::Watchdog::STOP: return core::GuardPolicy::Stop;
        case v1::SimulationBox::Watchdog::WARN: return core::GuardPolicy::Warn;
        default: throw InputError(prefix + ".watchdog." + field, std::to_string(p), "unknown policy");
      }
    };
    if (w.has_every_steps()) out.every_steps = w.every_steps();
    out.policy = policy(w.policy(), out.policy, "policy");
    out.speed_policy = policy(w.speed_policy(), out.speed_policy, "speed_policy");
    if (w.has_max_overlap_fraction()) out.max_overlap_fraction = w.max_overlap_fraction();
    if (w.has_max_energy_growth()) out.max_energy_growth = w.max_energy_growth();
    if (w.has_max_speed_factor()) out.max_speed_factor = w.max_speed_factor();
  }
  fidelity = applyFidelity(box, prefix, settings);  // after the explicit fields: they win
  settings.validate(prefix);
  return settings;
}

RunOptions toRunOptions(const v1::SimulationBox& box, const std::string& prefix, SceneUse use) {
  RunOptions run;
  run.field_prefix = prefix;
  run.end_time = box.end_time();
  if (use != SceneUse::Headless) {
    core::requireNonNegative(prefix + ".end_time", run.end_time);
  } else {
    core::requirePositive(prefix + ".end_time", run.end_time);
  }
  run.output_directory = box.output().directory();
  run.vtk_interval = box.output().vtk_interval();
  core::requireNonNegative(prefix + ".output.vtk_interval", run.vtk_interval);
  if (box.output().has_progress_interval_s()) run.progress_interval = box.output().progress_interval_s();
  core::requirePositive(prefix + ".output.progress_interval_s", run.progress_interval);
  run.checkpoint_interval = box.output().checkpoint_interval();
  core::requireNonNegative(prefix + ".output.checkpoint_interval", run.checkpoint_interval);
  run.contact_interval = box.output().contact_interval();
  core::requireNonNegative(prefix + ".output.contact_interval", run.contact_interval);
  run.mesh_loads = box.output().mesh_loads();
  // Co-simulation only, checked for every scene so a file is valid for both uses.
  core::requireInRange(prefix + ".coupling.client_timeout", box.coupling().client_timeout(), 0.0, kMaxWaitSeconds,
                       "s (0: the server's default)");
  for (int k = 0; k < box.coupling().expected_names_size(); ++k) {
    core::requireValidName(prefix + ".coupling.expected_names[" + std::to_string(k) + "]",
                           box.coupling().expected_names(k));
  }
  if (box.output().has_final_checkpoint()) run.final_checkpoint = box.output().final_checkpoint();
  if (box.output().has_final_particles_csv()) run.final_particles_csv = box.output().final_particles_csv();
  return run;
}

void addPlane(const v1::Plane& plane, const std::string& name, const MaterialNames& materials,
              const std::string& prefix, core::World& world) {
  core::PlaneSpec spec;
  spec.name = name;
  spec.point = toVec3(plane.point());
  if (!plane.has_normal()) throw InputError(prefix + ".normal", "(missing)", "a plane needs a normal");
  spec.normal = toVec3(plane.normal());
  spec.material = resolveMaterial(materials, plane.material(), prefix + ".material");
  spec.rigid = plane.rigid();
  world.addPlane(std::move(spec), prefix);
}

/// Parcels of factor alpha for a lattice of grains: sizes x alpha and counts / alpha per
/// axis (rounded, at least 1), so the lattice keeps its extent and, up to the rounding,
/// its mass. The grains' spec was validated; the scaled one satisfies the same rules.
void scaleLattice(LatticeSpec& spec, const core::CoarseGraining& coarse) {
  if (coarse.factor == 1.0) return;
  spec.radius = coarse.radius(spec.radius);
  if (spec.radius_max) spec.radius_max = coarse.radius(*spec.radius_max);
  spec.spacing = coarse.radius(spec.spacing);
  spec.jitter = coarse.radius(spec.jitter);
  for (std::uint32_t& n : spec.counts) {
    n = static_cast<std::uint32_t>(std::max(1.0, std::round(static_cast<double>(n) / coarse.factor)));
  }
}

void addLattice(const v1::ParticleLattice& lattice, const MaterialNames& materials,
                const core::CoarseGraining& coarse, const std::string& prefix, core::World& world) {
  LatticeSpec spec;
  spec.material = resolveMaterial(materials, lattice.material(), prefix + ".material");
  if (!lattice.clump_template().empty()) {
    addClumpLattice(lattice, spec.material, prefix, world);
    return;
  }
  spec.radius = lattice.radius();
  if (lattice.has_radius_max()) spec.radius_max = lattice.radius_max();
  spec.origin = toVec3(lattice.origin());
  spec.spacing = lattice.spacing();
  if (!lattice.has_counts()) throw InputError(prefix + ".counts", "(missing)", "required (nx, ny, nz)");
  spec.counts = {lattice.counts().nx(), lattice.counts().ny(), lattice.counts().nz()};
  spec.jitter = lattice.jitter();
  spec.seed = lattice.seed();
  spec.velocity = toVec3(lattice.velocity());
  spec.validate(prefix);
  scaleLattice(spec, coarse);
  requireParticleMemory(prefix + ".counts", spec.countText(), world.particles().size() + spec.count());
  for (const core::ParticleSpec& sphere : generateLattice(spec)) world.addParticle(sphere, prefix);
}

void addParticleFile(const v1::ParticleFile& file, const MaterialNames& materials,
                     const FileScope& files, const std::string& prefix, core::World& world) {
  const std::uint32_t material = resolveMaterial(materials, file.material(), prefix + ".material");
  const std::string path =
      resolveExistingSceneFile(file.path(), files, prefix + ".path", "a particle file path is required").string();
  for (const ParticleRecord& record : readParticleFile(path)) {
    core::ParticleSpec sphere;
    sphere.position = record.position;
    sphere.radius = record.radius;
    sphere.material = material;
    world.addParticle(sphere, path + ":line " + std::to_string(record.line));
  }
}

/// Builds the declared body and hands it to the engine.
void addMeshBody(const MeshBodyDeclaration& declaration, const std::string& prefix, core::World& world) {
  world.addMesh(buildMeshBody(declaration, prefix), prefix);
}

}  // namespace

TranslatedScene translateScene(const v1::Scene& scene, const FileScope& files, SceneUse use) {
  const int boxIndex = checkStructure(scene);
  const std::string boxPrefix = componentPath(boxIndex) + ".simulation_box";
  const v1::SimulationBox& box = scene.components(boxIndex).simulation_box();
  FidelityChoice fidelity;
  const core::CoarseGraining coarse{box.has_coarse_graining() ? box.coarse_graining() : 1.0};
  coarse.validate(boxPrefix + ".coarse_graining");
  core::SimulationSettings settings = toSettings(box, boxPrefix, coarse, fidelity);
  TranslatedScene out{core::World(std::move(settings), boxPrefix), toRunOptions(box, boxPrefix, use),
                      std::move(fidelity), coarse, {}};

  SceneMaterials declared = addMaterials(scene, box, boxPrefix, files, coarse, out.world);
  out.softening = std::move(declared.softening);
  const MaterialNames materials = std::move(declared.names);
  addMaterialPairs(scene, materials, coarse, out.world);
  addClumpTemplates(scene, out.world);
  const MaterialResolver resolve = [&](const std::string& name, const std::string& field) {
    return resolveMaterial(materials, name, field);
  };
  ClodGroups clods;  // of the pit generators, for their clod_bonds rules
  for (int i = 0; i < scene.components_size(); ++i) {
    const v1::ComponentDeclaration& component = scene.components(i);
    const std::string path = componentPath(i);
    switch (component.kind_case()) {
      case v1::ComponentDeclaration::kPlane:
        addPlane(component.plane(), component.name(), materials, path + ".plane", out.world);
        break;
      case v1::ComponentDeclaration::kParticleLattice:
        addLattice(component.particle_lattice(), materials, coarse, path + ".particle_lattice", out.world);
        break;
      case v1::ComponentDeclaration::kParticleFile:
        addParticleFile(component.particle_file(), materials, files, path + ".particle_file", out.world);
        break;
      case v1::ComponentDeclaration::kParticleSystem:
        addParticleSystem(component.particle_system(), files, path + ".particle_system", out.world);
        break;
      case v1::ComponentDeclaration::kMeshBody: {
        const std::string prefix = path + ".mesh_body";
        const v1::MeshBody& mesh = component.mesh_body();
        const std::uint32_t material = resolveMaterial(materials, mesh.material(), prefix + ".material");
        addMeshBody(translateMeshBody(mesh, component.name(), material, files, prefix), prefix, out.world);
        break;
      }
      case v1::ComponentDeclaration::kFacetBody: {
        const std::string prefix = path + ".facet_body";
        addMeshBody(translateFacetBody(component.facet_body(), component.name(), resolve, files, prefix),
                    prefix, out.world);
        break;
      }
      case v1::ComponentDeclaration::kRigidBody: {
        const std::string prefix = path + ".rigid_body";
        addMeshBody(translateRigidBody(component.rigid_body(), component.name(), resolve, files, prefix),
                    prefix, out.world);
        break;
      }
      case v1::ComponentDeclaration::kSingleParticle: {
        const std::string prefix = path + ".single_particle";
        const std::uint32_t material =
            resolveMaterial(materials, component.single_particle().material(), prefix + ".material");
        addSingleParticle(component.single_particle(), material, prefix, out.world);
        break;
      }
      case v1::ComponentDeclaration::kParticleSource: {
        const std::string prefix = path + ".particle_source";
        const std::uint32_t material =
            resolveMaterial(materials, component.particle_source().material(), prefix + ".material");
        addParticleSource(component.particle_source(), component.name(), material, coarse, prefix, out.world);
        break;
      }
      case v1::ComponentDeclaration::kPitGenerator: {
        const std::string prefix = path + ".pit_generator";
        const std::uint32_t material =
            resolveMaterial(materials, component.pit_generator().material(), prefix + ".material");
        core::PitSpec spec = pitSpec(component.pit_generator(), material, prefix, out.world);
        const std::string& clodBonds = component.pit_generator().clod_bonds();
        if (spec.clod_fraction > 0.0) {
          spec.clod_gap = clodBondGap(scene, clodBonds, prefix + ".clod_bonds");
          clods[clodBonds];  // its rule bonds only within clods, even when the pit made none
        }
        if (use != SceneUse::CosimCheck) {
          const core::PitReport report = core::generatePit(out.world, spec, component.name(), prefix);
          if (spec.clod_fraction > 0.0) addClodGroups(clods, clodBonds, report);
        }
        break;
      }
      case v1::ComponentDeclaration::kParticleSink:
      case v1::ComponentDeclaration::kRegionSensor:
      case v1::ComponentDeclaration::kFlowSensor:
      case v1::ComponentDeclaration::kTracker:  // after all mesh bodies: addSensorComponents
      case v1::ComponentDeclaration::kSimulationBox:
      case v1::ComponentDeclaration::kMaterial:
      case v1::ComponentDeclaration::kMaterialPair:
      case v1::ComponentDeclaration::kClumpTemplate:
      case v1::ComponentDeclaration::kParticleView:  // served by the co-simulation host, no engine object
      case v1::ComponentDeclaration::kMassSpringBody:  // after all mesh bodies: addDeformableBodies
      case v1::ComponentDeclaration::kFemBody:
      case v1::ComponentDeclaration::kParallelBonds:  // after every particle set: addParallelBonds
      case v1::ComponentDeclaration::KIND_NOT_SET:
        break;
    }
  }
  addDeformableBodies(scene, resolve, files, out.world);
  addSensorComponents(scene, out.world);
  addParallelBonds(scene, resolve, out.world, clods);
  requireOutputFileCount(out.world);
  if (out.run.mesh_loads && out.world.meshes().empty()) {
    throw core::InputError(out.run.field_prefix + ".output.mesh_loads", "true",
                           "the scene has no mesh bodies to put loads on");
  }
  return out;
}

std::vector<std::string> coarseGrainingReportLines(const core::CoarseGraining& coarse) {
  if (coarse.factor == 1.0) return {};
  return {fmt::format("coarse graining: factor {:g} (docs/accuracy.md): particle_lattice and particle_source make "
                      "parcels of {:g} x the grains' radius, each with the mass of {:.4g} grains (lattice counts / "
                      "{:g} per axis, rate_particles_per_s / {:.4g}, rate_kg_per_s kept); linear_normal_stiffness "
                      "x {:g}; cohesion_energy_density x {:g} (the bed Bond number kept); density, modulus, "
                      "restitution and friction kept",
                      coarse.factor, coarse.factor, std::pow(coarse.factor, 3), coarse.factor,
                      std::pow(coarse.factor, 3), coarse.linearStiffness(1.0), coarse.cohesionEnergyDensity(1.0))};
}

std::vector<std::string> choiceReportLines(const TranslatedScene& scene, const core::World& world) {
  std::vector<std::string> lines = fidelityReportLines(scene.fidelity, world);
  for (const std::vector<std::string>& more :
       {coarseGrainingReportLines(scene.coarse_graining), softeningReportLines(scene.softening)}) {
    lines.insert(lines.end(), more.begin(), more.end());
  }
  return lines;
}

}  // namespace demlink::server
