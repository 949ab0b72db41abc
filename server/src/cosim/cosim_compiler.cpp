/// Declaration collection and compilation (contract in cosim_compiler.hpp).
///
/// Order of the compile: find the SimulationBox; give sensors and sinks declared by a
/// client without a sample interval their communication interval (the translator needs
/// one); translate; convert every communication interval to whole steps
/// (core::intervalSteps: rounded with a warning, or refused in strict mode); initialise
/// the world, which checks the time step against the critical limit; resolve each
/// component's engine object; convert the end time and output intervals by the headless
/// rule (planRun); write the report. Every engine error comes back as InputError with a
/// "components[i]..." path and is renamed to "<name>...".
#include "demlink/server/cosim/cosim_compiler.hpp"

#include <google/protobuf/util/message_differencer.h>
#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>

#include "demlink/core/components/sampled_component.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/core/base/names.hpp"
#include "demlink/core/step/interval_steps.hpp"
#include "demlink/server/run/deformable_series.hpp"
#include "demlink/server/scene/translate_deformables.hpp"
#include "demlink/server/scene/translate_rigid_body.hpp"
#include "demlink/server/run/contact_output_plan.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {
namespace {

using Kind = v1::ComponentDeclaration;

/// Most time steps one communication interval may span. Why a cap: the host steps an
/// interval in one go on the server's only thread, so an interval of 1e15 steps (a valid
/// 1e-220 s time step, found by the host fuzzer) would stall every connection for ever.
/// 1e8 steps is minutes even for a handful of particles; no coupling needs more.
constexpr std::uint64_t kMaxStepsPerInterval = 100'000'000;

bool exchangeable(Kind::KindCase kind) {
  switch (kind) {
    case Kind::kSimulationBox:
    case Kind::kRigidBody:
    case Kind::kParticleSource:
    case Kind::kParticleSink:
    case Kind::kRegionSensor:
    case Kind::kFlowSensor:
    case Kind::kParticleView:
    case Kind::kMassSpringBody:
    case Kind::kFemBody: return true;
    default: return false;
  }
}

/// The engine's InputError as a fatal INVALID_DECLARATION naming the component by name.
CompileFailure failureOf(const core::InputError& error, const std::vector<DeclaredComponent>& all,
                         const std::string& fallbackComponent = {}) {
  const NamedField named = nameDeclaredField(error.field(), all);
  const std::string component = named.component ? all[*named.component].declaration.name() : fallbackComponent;
  const core::InputError renamed(named.field, error.value(), error.reason());
  return CompileFailure(makeError(v1::Error::INVALID_DECLARATION, renamed.what(), component, named.field, true));
}

CompileFailure failure(const std::string& component, const std::string& field, const std::string& value,
                       const std::string& reason) {
  return CompileFailure(
      makeError(v1::Error::INVALID_DECLARATION, core::InputError(field, value, reason).what(), component, field, true));
}

/// The file paths a declaration names: (field below the component, the path to rewrite).
std::vector<std::pair<std::string, std::string*>> filePathsOf(v1::ComponentDeclaration& c) {
  std::vector<std::pair<std::string, std::string*>> out;
  if (c.has_mesh_body()) out.emplace_back("mesh_body.stl_file", c.mutable_mesh_body()->mutable_stl_file());
  if (c.has_facet_body() && c.facet_body().has_stl_file()) {
    out.emplace_back("facet_body.stl_file", c.mutable_facet_body()->mutable_stl_file());
  }
  if (c.has_rigid_body() && c.rigid_body().has_stl_file()) {
    out.emplace_back("rigid_body.stl_file", c.mutable_rigid_body()->mutable_stl_file());
  }
  if (c.has_particle_file()) out.emplace_back("particle_file.path", c.mutable_particle_file()->mutable_path());
  if (c.has_particle_system() && c.particle_system().has_csv_file()) {
    out.emplace_back("particle_system.csv_file", c.mutable_particle_system()->mutable_csv_file());
  }
  if (c.has_particle_system() && c.particle_system().has_checkpoint_file()) {
    out.emplace_back("particle_system.checkpoint_file", c.mutable_particle_system()->mutable_checkpoint_file());
  }
  if (c.has_mass_spring_body() && c.mass_spring_body().has_stl_file()) {
    out.emplace_back("mass_spring_body.stl_file", c.mutable_mass_spring_body()->mutable_stl_file());
  }
  if (c.has_fem_body() && c.fem_body().has_mesh()) {
    out.emplace_back("fem_body.mesh.msh_file", c.mutable_fem_body()->mutable_mesh()->mutable_msh_file());
  }
  if (c.has_fem_body() && c.fem_body().has_matrices()) {
    v1::FemMatrices& m = *c.mutable_fem_body()->mutable_matrices();
    out.emplace_back("fem_body.matrices.mass_matrix_file", m.mutable_mass_matrix_file());
    out.emplace_back("fem_body.matrices.stiffness_matrix_file", m.mutable_stiffness_matrix_file());
    out.emplace_back("fem_body.matrices.damping_matrix_file", m.mutable_damping_matrix_file());
    out.emplace_back("fem_body.matrices.nodes_file", m.mutable_nodes_file());
    out.emplace_back("fem_body.matrices.triangles_file", m.mutable_triangles_file());
  }
  return out;
}

/// Where a client's files may be: under the data root, relative paths from it; without
/// one, nowhere.
FileScope clientFileScope(const std::optional<std::filesystem::path>& dataRoot) {
  FileScope scope;
  scope.anywhere = false;
  scope.roots_name = "the server's data root (--data-root)";
  scope.no_root_reason =
      "this server takes no file paths from clients (it runs without --data-root); send the geometry inline "
      "(rigid_body.stl_data or triangles)";
  if (dataRoot) {
    scope.anchor = *dataRoot;
    scope.roots = {*dataRoot};
  }
  return scope;
}

/// A sensor or sink from a client without its own sample schedule samples at its
/// communication interval.
template <class Sampled>
void defaultSampleInterval(Sampled& sampled, double communicationInterval) {
  if (sampled.sample_interval() == 0.0 && sampled.sample_every_steps() == 0 && communicationInterval > 0.0) {
    sampled.set_sample_interval(communicationInterval);
  }
}

/// The deformable body of a mass_spring_body / fem_body declaration and the nodes its
/// outputs report; InputError named "<name>.<kind>.output_nodes...".
void resolveDeformable(const v1::ComponentDeclaration& declaration, const core::World& world, CosimComponent& c) {
  const bool massSpring = declaration.has_mass_spring_body();
  const v1::DeformableOutputNodes& nodes =
      massSpring ? declaration.mass_spring_body().output_nodes() : declaration.fem_body().output_nodes();
  c.deformable_attached = !(massSpring ? declaration.mass_spring_body().attached_to()
                                       : declaration.fem_body().attached_to())
                               .empty();
  for (std::size_t k = 0; k < world.deformableBodies().size(); ++k) {
    const core::DeformableBody& body = *world.deformableBodies()[k];
    if (body.name() != c.name) continue;
    c.deformable = k;
    c.output_nodes = outputNodesOf(nodes, body.nodeCount(), body.surface().positions().size(),
                                   c.name + "." + c.kind + ".output_nodes");
  }
}

std::string reportText(const CompiledSimulation& out, const core::World& world) {
  const core::TimeStepReport& limit = world.timeStepReport();
  std::string text = fmt::format("compiled co-simulation: {} components, {} particles, {} meshes\n",
                                 out.components.size(), world.particles().size(), world.meshes().size());
  std::string stages;
  for (const std::string& stage : world.activeStages()) stages += (stages.empty() ? "" : ", ") + stage;
  text += "active stages: " + stages + "\n";
  text += "pair kernel: " + std::string(core::pairKernelName(world.pairKernel())) + "\n";
  const core::SimulationSettings& settings = world.settings();
  text += fmt::format("threads: {}{}\n", settings.threads,
                      settings.threads_choice.empty() ? std::string() : " (" + settings.threads_choice + ")");
  text += fmt::format("time step: {:.6g} s = {:.1f} % of the critical {:.6g} s (limited by {})\n", out.time_step,
                      100.0 * out.time_step / limit.limit, limit.limit, limit.limited_by);
  for (const std::string& line : limit.describe()) text += line + "\n";
  text += out.end_step > 0 ? fmt::format("end step: {} (t = {:.6g} s)\n", out.end_step,
                                         static_cast<double>(out.end_step) * out.time_step)
                           : std::string("end step: none (until every client said Bye)\n");
  for (const CosimComponent& c : out.components) {
    text += fmt::format("  [{}] {} ({}){}: {}\n", c.id, c.name, c.kind, c.owner ? " remote" : "",
                        c.interval_steps > 0 ? fmt::format("every {} steps ({:.6g} s)", c.interval_steps,
                                                           static_cast<double>(c.interval_steps) * out.time_step)
                                             : std::string("not exchanged"));
  }
  for (const std::string& line : deformableReportLines(world)) text += line + "\n";
  for (const std::string& line : choiceReportLines(*out.scene, world)) {
    if (!line.starts_with("warning: ")) text += line + "\n";
  }
  for (const std::string& warning : out.report.warnings()) text += "warning: " + warning + "\n";
  return text;
}

}  // namespace

NamedField nameDeclaredField(const std::string& field, const std::vector<DeclaredComponent>& all) {
  static const std::string kPrefix = "components[";
  if (!field.starts_with(kPrefix)) return {field, std::nullopt};
  const std::size_t close = field.find(']');
  if (close == std::string::npos) return {field, std::nullopt};
  std::size_t index = 0;
  const char* first = field.data() + kPrefix.size();
  const char* last = field.data() + close;
  const auto [end, error] = std::from_chars(first, last, index);
  if (error != std::errc() || end != last || index >= all.size()) return {field, std::nullopt};
  return {all[index].declaration.name() + field.substr(close + 1), index};
}

v1::Error makeError(v1::Error::Code code, const std::string& message, const std::string& component,
                    const std::string& field, bool fatal) {
  v1::Error error;
  error.set_code(code);
  // The last guard on size: the parts from outside are cut where they are quoted.
  error.set_message(core::cutText(message));
  error.set_component(core::cutText(component, core::kLogTextMaxBytes));
  error.set_field(core::cutText(field, core::kLogTextMaxBytes));
  error.set_fatal(fatal);
  return error;
}

CosimCompiler::CosimCompiler(v1::Scene baseScene) {
  for (const v1::ComponentDeclaration& d : baseScene.components()) declared_.push_back({d, std::nullopt});
  base_count_ = declared_.size();
}

void CosimCompiler::reset() { declared_.resize(base_count_); }

void CosimCompiler::withdraw(ConnectionId owner) {
  std::erase_if(declared_, [&](const DeclaredComponent& d) { return d.owner == owner; });
}

bool CosimCompiler::isRepeat(ConnectionId owner, const v1::ComponentDeclaration& declaration) const {
  return std::any_of(declared_.begin(), declared_.end(), [&](const DeclaredComponent& d) {
    return d.owner == owner && d.declaration.name() == declaration.name() &&
           google::protobuf::util::MessageDifferencer::Equals(d.declaration, declaration);
  });
}

const v1::SimulationBox* CosimCompiler::box() const {
  for (const DeclaredComponent& d : declared_) {
    if (d.declaration.has_simulation_box()) return &d.declaration.simulation_box();
  }
  return nullptr;
}

std::optional<v1::Error> CosimCompiler::declare(ConnectionId owner, const v1::ComponentDeclaration& declaration) {
  const std::string& name = declaration.name();
  if (declaration.kind_case() == Kind::KIND_NOT_SET) {
    return makeError(v1::Error::UNKNOWN_COMPONENT_KIND,
                     "component " + core::quotedLogText(name) + " declares no kind this server knows (one of simulation_box, "
                     "material, plane, rigid_body, particle_source, particle_sink, region_sensor, flow_sensor, "
                     "particle_view, ...)",
                     name, "component.kind");
  }
  if (name.empty()) {
    return makeError(v1::Error::DUPLICATE_NAME, "every component needs a non-empty name (a " +
                                                    componentKindName(declaration.kind_case()) + " has none)",
                     name, "component.name");
  }
  if (std::string problem = core::nameProblem(name); !problem.empty()) {
    return makeError(v1::Error::INVALID_DECLARATION,
                     "component.name = " + core::quotedLogText(name, 64) + ": " + problem, "", "component.name");
  }
  for (const DeclaredComponent& d : declared_) {
    if (d.declaration.name() == name) {
      return makeError(v1::Error::DUPLICATE_NAME,
                       "component name \"" + name + "\" is already declared (" +
                           (d.owner ? "by a client" : std::string("by the scene file")) + ")",
                       name, "component.name");
    }
  }
  if (declaration.has_simulation_box() && box() != nullptr) {
    return makeError(v1::Error::INVALID_DECLARATION,
                     "a second simulation_box (\"" + name + "\"): a simulation has exactly one", name,
                     "component.simulation_box");
  }
  // Clients' declarations are kept sorted by name (after the scene file's, in file order):
  // clients that connect at the same time declare in a racy order, and the compiled world
  // (ids, particle order) must not depend on it, or the same co-simulation would not give
  // the same results run after run (found by the multi-host test).
  const auto position = std::upper_bound(
      declared_.begin() + static_cast<std::ptrdiff_t>(base_count_), declared_.end(), name,
      [](const std::string& n, const DeclaredComponent& d) { return n < d.declaration.name(); });
  declared_.insert(position, {declaration, owner});
  return std::nullopt;
}

bool CosimCompiler::usesQuietPeriod() const {
  const v1::SimulationBox* b = box();
  return b == nullptr || (b->coupling().expected_count() == 0 && b->coupling().expected_names().empty());
}

bool CosimCompiler::expectedSetComplete() const {
  const v1::SimulationBox* b = box();
  if (b == nullptr || usesQuietPeriod()) return false;
  if (b->coupling().expected_count() > 0 && declared_.size() >= b->coupling().expected_count()) return true;
  if (b->coupling().expected_names().empty()) return false;
  return std::all_of(b->coupling().expected_names().begin(), b->coupling().expected_names().end(),
                     [&](const std::string& name) {
                       return std::any_of(declared_.begin(), declared_.end(), [&](const DeclaredComponent& d) {
                         return d.declaration.name() == name;
                       });
                     });
}

CosimCompiler::Missing CosimCompiler::missing() const {
  const v1::SimulationBox* b = box();
  if (b == nullptr) return {"simulation_box", "no simulation_box declared yet"};
  std::string boxName;
  for (const DeclaredComponent& d : declared_) {
    if (d.declaration.has_simulation_box()) boxName = d.declaration.name();
  }
  const std::string coupling = boxName + ".simulation_box.coupling";
  if (b->coupling().expected_count() > 0) {
    return {coupling + ".expected_count", fmt::format("{} of the {} expected components declared", declared_.size(),
                                                      b->coupling().expected_count())};
  }
  if (!b->coupling().expected_names().empty()) {
    std::vector<std::string> names;
    for (const std::string& name : b->coupling().expected_names()) {
      const bool declared = std::any_of(declared_.begin(), declared_.end(),
                                        [&](const DeclaredComponent& d) { return d.declaration.name() == name; });
      if (!declared) names.push_back(name);
    }
    return {coupling + ".expected_names", "not declared yet: " + core::quotedLogList(names)};
  }
  return {"declare", fmt::format("{} components declared and declarations still arriving", declared_.size())};
}

CompiledSimulation CosimCompiler::compile(const std::filesystem::path& sceneDirectory,
                                          const std::optional<std::filesystem::path>& dataRoot) const {
  const v1::SimulationBox* simulationBox = box();
  if (simulationBox == nullptr) {
    throw failure("", "simulation_box", "(none)",
                  "no simulation_box declared (the scene file or a client must declare exactly one)");
  }
  v1::Scene scene;
  const FileScope clientFiles = clientFileScope(dataRoot);
  for (const DeclaredComponent& d : declared_) {
    v1::ComponentDeclaration& c = *scene.add_components();
    c = d.declaration;
    if (!d.owner) continue;
    // A client's paths are checked against the data root here and handed on resolved, so
    // the translator (whose roots include the scene file's folder) sees only paths that
    // passed this check.
    for (const auto& [field, path] : filePathsOf(c)) {
      if (path->empty()) continue;  // the translator names the missing path
      try {
        *path = resolveExistingSceneFile(*path, clientFiles, c.name() + "." + field).string();
      } catch (const core::InputError& error) {
        throw failure(c.name(), error.field(), error.value(), error.reason());
      }
    }
    const double interval = c.communication_interval();
    if (c.has_particle_sink()) defaultSampleInterval(*c.mutable_particle_sink(), interval);
    if (c.has_region_sensor()) defaultSampleInterval(*c.mutable_region_sensor(), interval);
    if (c.has_flow_sensor()) defaultSampleInterval(*c.mutable_flow_sensor(), interval);
  }

  FileScope files(sceneDirectory);
  if (dataRoot && !files.anywhere) files.roots.push_back(*dataRoot);
  CompiledSimulation out;
  try {
    out.scene = std::make_unique<TranslatedScene>(translateScene(scene, files, SceneUse::Cosim));
  } catch (const core::InputError& error) {
    throw failureOf(error, declared_);
  }
  core::World& world = out.scene->world;
  out.time_step = world.settings().time_step;
  const double dt = out.time_step;
  const v1::SimulationBox::Coupling& coupling = simulationBox->coupling();
  out.client_timeout_s = coupling.client_timeout();

  for (std::size_t i = 0; i < declared_.size(); ++i) {
    const DeclaredComponent& d = declared_[i];
    if (d.declaration.has_simulation_box()) out.box_name = d.declaration.name();
    CosimComponent c;
    c.name = d.declaration.name();
    c.kind_case = d.declaration.kind_case();
    c.kind = componentKindName(c.kind_case);
    c.id = static_cast<std::uint32_t>(i + 1);
    c.owner = d.owner;
    const std::string field = c.name + ".communication_interval";
    const double interval = d.declaration.communication_interval();
    if (!std::isfinite(interval) || interval < 0.0) {
      throw failure(c.name, field, core::formatValue(interval), "must be finite and >= 0 [s]");
    }
    if (c.kind_case == Kind::kRigidBody) {
      c.motion = rigidBodyMotion(d.declaration.rigid_body(), c.name + ".rigid_body");
      for (std::size_t m = 0; m < world.meshes().size(); ++m) {
        if (world.meshes()[m].name() == c.name) c.mesh = m;
      }
      if (d.owner && interval == 0.0) {
        throw failure(c.name, field, "0", "a rigid_body declared by a client needs a communication interval > 0");
      }
    }
    if (c.kind_case == Kind::kMassSpringBody || c.kind_case == Kind::kFemBody) {
      try {
        resolveDeformable(d.declaration, world, c);
      } catch (const core::InputError& error) {
        throw failure(c.name, error.field(), error.value(), error.reason());
      }
    }
    if (c.kind_case == Kind::kParticleView && d.declaration.particle_view().max_count() > 0) {
      c.view_max_count = d.declaration.particle_view().max_count();
    }
    for (const auto& component : world.components()) {
      if (component->name() == c.name) c.engine = component.get();
    }
    if (interval > 0.0) {
      if (!d.owner) {
        out.report.add_warnings(c.name + ".communication_interval: a scene-file component is not exchanged");
      } else if (!exchangeable(c.kind_case)) {
        throw failure(c.name, field, core::formatValue(interval),
                      "a " + c.kind + " has no inputs or outputs to exchange; use 0");
      } else {
        core::IntervalRule rule;
        rule.strict = coupling.strict_intervals();
        rule.max_steps = kMaxStepsPerInterval;
        rule.max_steps_why = "per exchange (the server steps an interval in one go): use a shorter interval or a "
                             "larger time step";
        core::IntervalSteps steps;
        try {
          steps = core::intervalSteps(field, interval, dt, rule);
        } catch (const core::InputError& error) {
          throw failureOf(error, declared_, c.name);
        }
        if (!steps.warning.empty()) out.report.add_warnings(steps.warning);
        c.interval_steps = steps.steps;
      }
    }
    out.components.push_back(std::move(c));
  }

  // The same seconds -> steps rule as a headless run (run_driver.hpp); end_time 0: until
  // every client said Bye. Planned first: the contact output it asks for must be on
  // before initialize(), whose force evaluation is the contacts' step-0 frame.
  try {
    out.plan = planRun(out.scene->run, dt, false);
    const core::ContactOutputSettings contacts = contactOutputOf(out.scene->run, out.plan);
    if (contacts.active()) world.setContactOutput(contacts);
    // The world names its settings by the box's scene path (translateScene), which
    // failureOf turns into the box's component name.
    world.initialize();
  } catch (const core::InputError& error) {
    throw failureOf(error, declared_, out.box_name);
  }
  out.end_step = out.plan.end_step;
  // End time 0 runs until every client said Bye; with nothing exchanged the world never
  // advances, and the one running simulation would hold the server for as long as its
  // clients stay connected.
  const bool anyExchanged = std::any_of(out.components.begin(), out.components.end(),
                                        [](const CosimComponent& c) { return c.interval_steps > 0; });
  if (out.end_step == 0 && !anyExchanged) {
    throw failure(out.box_name, out.box_name + ".simulation_box.end_time", "0",
                  "the simulation could never advance: end_time 0 runs until every client said Bye, which needs at "
                  "least one component a client exchanges (communication_interval > 0); give an end_time > 0 or "
                  "exchange a component");
  }
  // Warnings name the component as errors do ("box.simulation_box.output.vtk_interval").
  for (const std::string& warning : out.plan.warnings) {
    out.report.add_warnings(nameDeclaredField(warning, declared_).field);
  }
  for (const std::string& warning : core::sampleScheduleWarnings(world.components())) {
    out.report.add_warnings(nameDeclaredField(warning, declared_).field);
  }
  for (const std::string& stage : world.activeStages()) out.report.add_active_stages(stage);
  out.report.set_time_step(dt);
  out.report.set_critical_time_step(world.timeStepReport().limit);
  out.report.set_particle_count(world.particles().size());
  for (const core::MeshBody& mesh : world.meshes()) {
    for (const std::string& warning : mesh.loadWarnings()) out.report.add_warnings(mesh.name() + ": " + warning);
  }
  for (const std::string& line : choiceReportLines(*out.scene, world)) {
    if (line.starts_with("warning: ")) out.report.add_warnings(line.substr(9));
  }
  out.report.set_text(reportText(out, world));
  return out;
}

}  // namespace demlink::server
