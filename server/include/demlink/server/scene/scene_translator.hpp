#pragma once
/// The scene compiler: the only place where protobuf declarations become engine
/// objects (docs: DESIGN.md, "compiler").
///
/// It validates the whole declaration set before anything runs and names every
/// problem by its path in the scene, e.g. "components[2].material.youngs_modulus"
/// or "components[3].plane.material" = "stel": unknown material. Rules:
///   - exactly one simulation_box; component names non-empty and unique;
///   - materials are registered first (declaration order), so a plane may
///     precede the material it names; material names are unique;
///   - omitted optional scalars take core::SimulationSettings / core::Material
///     defaults; relative file paths are relative to the scene file's directory;
///   - particles are added in declaration order (their ids follow it).
#include <filesystem>
#include <string>
#include <vector>

#include "demlink/core/particles/coarse_graining.hpp"
#include "demlink/core/world.hpp"
#include "demlink/server/scene/run_options.hpp"
#include "demlink/server/scene/fidelity_preset.hpp"
#include "demlink/server/scene/translate_materials.hpp"
#include "demlink/server/scene/translate_mesh_body.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// A compiled scene: the engine world (not yet initialised) and the run options.
struct TranslatedScene {
  core::World world;
  RunOptions run;
  FidelityChoice fidelity;  ///< what SimulationBox.fidelity chose, for the compile report
  core::CoarseGraining coarse_graining;  ///< SimulationBox.coarse_graining (factor 1: none)
  ModulusSoftening softening;            ///< SimulationBox.modulus_scale (factor 1: none)
};

/// The compile report's line for a coarse-graining factor (none for factor 1).
[[nodiscard]] std::vector<std::string> coarseGrainingReportLines(const core::CoarseGraining& coarse);

/// The compile report's lines of the box's speed/accuracy choices in `world` (the scene's,
/// initialised): the fidelity preset's, the coarse graining's and the softening's, warnings
/// as lines starting "warning: ". Headless runs and co-simulations print the same.
[[nodiscard]] std::vector<std::string> choiceReportLines(const TranslatedScene& scene, const core::World& world);

/// What the scene is translated for. A co-simulation may run without an end time
/// (end_time 0: until every client said Bye); a headless run needs one. CosimCheck is
/// the server's start-up check of its scene file: as Cosim, but a pit_generator's fields
/// are checked without settling the pit (each compile settles it).
enum class SceneUse { Headless, Cosim, CosimCheck };

/// Validates and translates a scene. `files` anchors relative paths and says where the
/// files it names may be (a scene file's folder converts to the scope of that folder).
/// Throws core::InputError naming the offending field (for a mesh_body whose
/// STL cannot be read: "<component>.mesh_body.stl_file").
[[nodiscard]] TranslatedScene translateScene(const v1::Scene& scene, const FileScope& files,
                                             SceneUse use = SceneUse::Headless);

}  // namespace demlink::server
