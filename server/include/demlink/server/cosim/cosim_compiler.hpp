#pragma once
/// The co-simulation compiler (docs/cosim.md, "Compiler"): collects the declarations of a
/// simulation (the scene file's and the clients', each tagged with its owner), decides when
/// the set is complete, and turns it into one engine world plus the exchange plan.
///
/// Why it reuses translateScene: a co-simulation is a scene whose components partly come
/// over the network. Building one v1::Scene and translating it keeps one compiler and one
/// set of validation rules for headless and coupled runs; this class adds only what is
/// specific to coupling (owners, communication intervals, ids, compile triggers) and
/// renames the translator's "components[i]" paths to component names, which is what a
/// client knows.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "demlink/core/walls/coupled_motion.hpp"
#include "demlink/core/components/world_component.hpp"
#include "demlink/server/cosim/cosim_host.hpp"
#include "demlink/server/run/run_driver.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "demlink/v1/protocol.pb.h"

namespace demlink::server {

/// A v1::Error with the given fields.
[[nodiscard]] v1::Error makeError(v1::Error::Code code, const std::string& message, const std::string& component = {},
                                  const std::string& field = {}, bool fatal = false);

/// A refused compile: the Error every connection receives.
struct CompileFailure : std::runtime_error {
  explicit CompileFailure(v1::Error e) : std::runtime_error(e.message()), error(std::move(e)) {}
  v1::Error error;
};

/// One declared component.
struct DeclaredComponent {
  v1::ComponentDeclaration declaration;
  std::optional<ConnectionId> owner;  ///< nullopt: from the scene file
};

/// A field path with its component named, as a client sees it.
struct NamedField {
  std::string field;                     ///< "<name>.<rest>", or the path as it was
  std::optional<std::size_t> component;  ///< index into the declarations
};

/// The one rule for the engine's field paths: the scene's "components[i].<rest>" (what
/// translateScene and the backend's refusals name) becomes "<name of declaration i>.<rest>";
/// any other path is kept, with no component.
[[nodiscard]] NamedField nameDeclaredField(const std::string& field, const std::vector<DeclaredComponent>& all);

/// One component of a compiled simulation and its engine handles.
struct CosimComponent {
  std::string name;
  std::string kind;  ///< the ComponentDeclaration field name, e.g. "rigid_body"
  v1::ComponentDeclaration::KindCase kind_case = v1::ComponentDeclaration::KIND_NOT_SET;
  std::uint32_t id = 0;              ///< [-], >= 1
  std::uint64_t interval_steps = 0;  ///< [-]; 0: not exchanged
  std::optional<ConnectionId> owner;
  std::optional<std::size_t> mesh;            ///< rigid_body: index into World::meshes()
  core::MotionMode motion = core::MotionMode::Predicted;  ///< rigid_body
  core::WorldComponent* engine = nullptr;     ///< source, sink, region and flow sensor
  std::uint32_t view_max_count = 10000;       ///< particle_view [-]
  /// mass_spring_body / fem_body: index into World::deformableBodies(), whether a mesh
  /// drives it (attached_to: no pose input), and the nodes its outputs report.
  std::optional<std::size_t> deformable;
  bool deformable_attached = false;
  std::vector<std::uint32_t> output_nodes;
};

/// What compile() builds.
struct CompiledSimulation {
  std::unique_ptr<TranslatedScene> scene;  ///< world initialised (time step checked)
  std::vector<CosimComponent> components;  ///< scene-file components first, then clients' in order
  std::string box_name;
  double time_step = 0.0;       ///< [s]
  std::uint64_t end_step = 0;   ///< [-]; 0: until every client said Bye (= plan.end_step)
  RunPlan plan;                 ///< end step and output intervals in steps
  double client_timeout_s = 0;  ///< SimulationBox.coupling.client_timeout [s]; 0: the server's default
  v1::CompileReport report;
};

class CosimCompiler {
 public:
  explicit CosimCompiler(v1::Scene baseScene);

  /// Stores a client's declaration, or returns the Error refusing it (UNKNOWN_COMPONENT_KIND,
  /// DUPLICATE_NAME, INVALID_DECLARATION for a second simulation_box); nothing is stored then.
  std::optional<v1::Error> declare(ConnectionId owner, const v1::ComponentDeclaration& declaration);
  /// `owner` already declared exactly this component (same name, equal message): a repeated
  /// initialisation, to be ignored rather than refused as a duplicate name.
  [[nodiscard]] bool isRepeat(ConnectionId owner, const v1::ComponentDeclaration& declaration) const;
  /// Forgets every declaration of `owner` (it left before the compile).
  void withdraw(ConnectionId owner);
  /// Back to the scene file's declarations only.
  void reset();

  /// The SimulationBox names its expected set (count or names) and it is complete.
  [[nodiscard]] bool expectedSetComplete() const;
  /// Neither expected_count nor expected_names is given (or there is no SimulationBox yet):
  /// the compile waits for the quiet period.
  [[nodiscard]] bool usesQuietPeriod() const;
  /// What the declared set still lacks, for the assembly timeout's Error: the field that
  /// made the set incomplete (e.g. "box.simulation_box.coupling.expected_count", or
  /// "simulation_box" when none is declared yet) and a sentence saying what is missing.
  struct Missing {
    std::string field;
    std::string what;
  };
  [[nodiscard]] Missing missing() const;
  [[nodiscard]] const std::vector<DeclaredComponent>& declarations() const { return declared_; }

  /// Compiles the declared set. Throws CompileFailure with Error{INVALID_DECLARATION, fatal}
  /// naming the component and the field ("<name>.<kind>.<field>"). The scene file's
  /// components name files in `sceneDirectory` or below (or under `dataRoot`); a client's
  /// only under `dataRoot`, relative to it, and none without one.
  [[nodiscard]] CompiledSimulation compile(const std::filesystem::path& sceneDirectory,
                                           const std::optional<std::filesystem::path>& dataRoot = std::nullopt) const;

 private:
  [[nodiscard]] const v1::SimulationBox* box() const;

  std::size_t base_count_ = 0;
  std::vector<DeclaredComponent> declared_;
};

}  // namespace demlink::server
