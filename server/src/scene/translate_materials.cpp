/// Materials family translation (see translate_materials.hpp). Kept apart from
/// scene_translator.cpp so the database and pair-override rules live in one
/// place; the compiler calls in with a few lines.
#include "demlink/server/scene/translate_materials.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/core/base/names.hpp"
#include "demlink/core/materials/material_database.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {
namespace {

using core::InputError;

std::uint32_t pairMaterial(const std::map<std::string, std::uint32_t>& materials, const std::string& name,
                           const std::string& field) {
  if (name.empty()) throw InputError(field, "\"\"", "a material name is required");
  const auto it = materials.find(name);
  if (it != materials.end()) return it->second;
  std::string declared;
  for (const auto& entry : materials) declared += (declared.empty() ? "" : ", ") + entry.first;
  throw InputError(field, core::quotedLogText(name), "unknown material (declared: " + (declared.empty() ? "none" : declared) + ")");
}

/// The built-in database, with the scene's materials file when it names one.
core::MaterialDatabase sceneMaterialDatabase(const std::string& materialsFile, const FileScope& files,
                                             const std::string& field) {
  if (materialsFile.empty()) return core::MaterialDatabase::builtIn();
  const std::filesystem::path path =
      resolveExistingSceneFile(materialsFile, files, field, "a materials file path is required");
  try {
    return core::MaterialDatabase::builtInWith(core::MaterialDatabase::fromFile(path));
  } catch (const InputError& error) {
    throw error.as(field);
  }
}

/// The softening box.modulus_scale asks for (factor 1 when not given), with the cohesive
/// materials and material pairs it softens.
ModulusSoftening chooseSoftening(const v1::Scene& scene, const v1::SimulationBox& box, const std::string& boxPrefix,
                                 const std::vector<core::Material>& materials) {
  ModulusSoftening out;
  if (!box.has_modulus_scale()) return out;
  out.factor = box.modulus_scale();
  // Written so that NaN fails too.
  if (!(out.factor > 0.0 && out.factor <= 1.0)) {
    throw InputError(boxPrefix + ".modulus_scale", core::formatValue(out.factor),
                     "must be in (0, 1]: a softening factor of Young's modulus");
  }
  for (const core::Material& m : materials) {
    if (m.cohesion_energy_density > 0.0) out.cohesive.push_back("material " + m.name);
  }
  for (const v1::ComponentDeclaration& c : scene.components()) {
    if (c.has_material_pair() && c.material_pair().cohesion_energy_density() > 0.0) {
      out.cohesive.push_back("material_pair " + c.name());
    }
  }
  return out;
}

}  // namespace

core::Material translateMaterial(const v1::Material& declared, const std::string& componentName,
                                 const std::string& fieldPrefix, const core::MaterialDatabase& database) {
  core::Material material;
  if (!declared.database_name().empty()) {
    material = database.at(declared.database_name(), fieldPrefix + ".database_name").material;
  }
  material.name = declared.name().empty() ? componentName : declared.name();
  core::requireValidName(fieldPrefix + ".name", material.name);
  if (declared.has_density()) material.density = declared.density();
  if (declared.has_youngs_modulus()) material.youngs_modulus = declared.youngs_modulus();
  if (declared.has_poisson_ratio()) material.poisson_ratio = declared.poisson_ratio();
  if (declared.has_restitution()) material.restitution = declared.restitution();
  if (declared.has_sliding_friction()) material.sliding_friction = declared.sliding_friction();
  if (declared.has_rolling_friction()) material.rolling_friction = declared.rolling_friction();
  if (declared.has_cohesion_energy_density()) material.cohesion_energy_density = declared.cohesion_energy_density();
  material.validate(fieldPrefix);
  return material;
}

std::vector<std::string> softeningReportLines(const ModulusSoftening& softening) {
  if (softening.factor == 1.0) return {};
  std::vector<std::string> lines{fmt::format(
      "modulus_scale {:g} (docs/accuracy.md \"Softening\"): every material's Young's modulus x {:g} for its contacts; "
      "the contacts' time-step limits grow {:.2f}-{:.2f}x",
      softening.factor, softening.factor, std::pow(softening.factor, -0.4), std::pow(softening.factor, -0.5))};
  for (const std::string& name : softening.cohesive) {
    lines.push_back("warning: modulus_scale " + core::formatValue(softening.factor) + " softens cohesive " + name +
                    ": its cohesion grows with the contact area; recalibrate cohesion_energy_density "
                    "(docs/materials.md)");
  }
  return lines;
}

SceneMaterials addMaterials(const v1::Scene& scene, const v1::SimulationBox& box, const std::string& boxPrefix,
                            const FileScope& files, const core::CoarseGraining& coarse, core::World& world) {
  const core::MaterialDatabase database =
      sceneMaterialDatabase(box.materials_file(), files, boxPrefix + ".materials_file");
  std::vector<core::Material> declared;
  std::map<std::string, int> declaredBy;
  for (int i = 0; i < scene.components_size(); ++i) {
    const v1::ComponentDeclaration& component = scene.components(i);
    if (!component.has_material()) continue;
    const std::string prefix = componentPath(i) + ".material";
    core::Material material = translateMaterial(component.material(), component.name(), prefix, database);
    material.cohesion_energy_density = coarse.cohesionEnergyDensity(material.cohesion_energy_density);
    const auto [it, inserted] = declaredBy.emplace(material.name, i);
    if (!inserted) {
      throw InputError(prefix + ".name", core::quotedLogText(material.name),
                       "material name already used by " + componentPath(it->second));
    }
    declared.push_back(std::move(material));
  }
  SceneMaterials out;
  out.softening = chooseSoftening(scene, box, boxPrefix, declared);
  for (core::Material& material : declared) {
    material.youngs_modulus *= out.softening.factor;
    out.names.emplace(material.name, world.addMaterial(material));
  }
  return out;
}

void addMaterialPairs(const v1::Scene& scene, const std::map<std::string, std::uint32_t>& materials,
                      const core::CoarseGraining& coarse, core::World& world) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> declaredBy;
  for (int i = 0; i < scene.components_size(); ++i) {
    const v1::ComponentDeclaration& component = scene.components(i);
    if (!component.has_material_pair()) continue;
    const v1::MaterialPair& pair = component.material_pair();
    const std::string prefix = componentPath(i) + ".material_pair";
    const std::uint32_t a = pairMaterial(materials, pair.material_a(), prefix + ".material_a");
    const std::uint32_t b = pairMaterial(materials, pair.material_b(), prefix + ".material_b");
    core::PairOverride values;
    if (pair.has_restitution()) values.restitution = pair.restitution();
    if (pair.has_sliding_friction()) values.sliding_friction = pair.sliding_friction();
    if (pair.has_rolling_friction()) values.rolling_friction = pair.rolling_friction();
    if (pair.has_cohesion_energy_density()) {
      values.cohesion_energy_density = coarse.cohesionEnergyDensity(pair.cohesion_energy_density());
    }
    if (!values.restitution && !values.sliding_friction && !values.rolling_friction &&
        !values.cohesion_energy_density) {
      throw InputError(prefix, core::quotedLogText(component.name()),
                       "overrides nothing (give restitution, sliding_friction, rolling_friction and/or "
                       "cohesion_energy_density)");
    }
    const auto [it, inserted] = declaredBy.emplace(std::minmax(a, b), i);
    if (!inserted) {
      throw InputError(prefix + ".material_b", core::quotedLogText(pair.material_b()),
                       "the pair " + pair.material_a() + " / " + pair.material_b() +
                           " is already overridden by components[" + std::to_string(it->second) + "]");
    }
    world.setPairOverride(a, b, values, prefix);
  }
}

}  // namespace demlink::server
