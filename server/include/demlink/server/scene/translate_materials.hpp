#pragma once
/// Scene translation of the materials family: Material declarations (with an
/// optional materials-database base) and MaterialPair overrides. Called by the
/// scene compiler (scene_translator.cpp); docs/materials.md describes the rules.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "demlink/core/materials/material.hpp"
#include "demlink/core/particles/coarse_graining.hpp"
#include "demlink/core/world.hpp"
#include "demlink/server/scene/proto_convert.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::core {
class MaterialDatabase;
}  // namespace demlink::core

namespace demlink::server {

/// A Material declaration as an engine material: the entry of `database` named by
/// database_name (if any) or core::Material's defaults, then every field given
/// explicitly. The name defaults to the component's name. Throws
/// core::InputError naming `fieldPrefix + ".<field>"` (an unknown database_name
/// lists the known names).
[[nodiscard]] core::Material translateMaterial(const v1::Material& declared, const std::string& componentName,
                                               const std::string& fieldPrefix, const core::MaterialDatabase& database);

/// How much the scene's contact moduli are softened (SimulationBox.modulus_scale).
struct ModulusSoftening {
  double factor = 1.0;                ///< every material's Young's modulus is multiplied by it [-]
  std::vector<std::string> cohesive;  ///< "material NAME" / "material_pair NAME" with cohesion (they get stickier)
};

/// The compile report's lines for `softening`: none for factor 1, else the factor and the
/// limit's gain, and a "warning: " line per cohesive material or material pair it softens.
[[nodiscard]] std::vector<std::string> softeningReportLines(const ModulusSoftening& softening);

/// The world indices of the scene's materials by name, and their softening.
struct SceneMaterials {
  std::map<std::string, std::uint32_t> names;
  ModulusSoftening softening;
};

/// Registers every material component with the world, in declaration order (its cohesion
/// through `coarse`'s law, its Young's modulus times box.modulus_scale, which must be in
/// (0, 1]: else core::InputError naming `boxPrefix + ".modulus_scale"`).
/// database_name values are looked
/// up in the built-in database and, when `box.materials_file` is given, in that file
/// (resolved against `files`). Throws core::InputError naming
/// `boxPrefix + ".materials_file"` for a file that is missing, outside the scene's
/// folders, malformed or names a built-in material again (the place in the file and the
/// reason follow), and "components[i].material.<field>" for a material's own errors.
[[nodiscard]] SceneMaterials addMaterials(const v1::Scene& scene, const v1::SimulationBox& box,
                                          const std::string& boxPrefix, const FileScope& files,
                                          const core::CoarseGraining& coarse, core::World& world);

/// Registers every material_pair component with the world. `materials` maps
/// declared material names to world indices. Throws core::InputError naming
/// "components[i].material_pair.<field>" for an unknown material, a bad value
/// or a pair overridden twice. A cohesion energy density goes through `coarse`'s law.
void addMaterialPairs(const v1::Scene& scene, const std::map<std::string, std::uint32_t>& materials,
                      const core::CoarseGraining& coarse, core::World& world);

}  // namespace demlink::server
