/// Translation of parallel bonds (contract in translate_bonds.hpp). Field paths follow the
/// JSON: "components[i].parallel_bonds.<field>", "...region.box.size", "...materials[k]".
#include "demlink/server/scene/translate_bonds.hpp"

#include <algorithm>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/step/interval_steps.hpp"
#include "demlink/server/scene/proto_convert.hpp"
#include "demlink/server/scene/translate_sensors.hpp"

namespace demlink::server {

double clodBondGap(const v1::Scene& scene, const std::string& bondsName, const std::string& clodBondsField) {
  for (int i = 0; i < scene.components_size(); ++i) {
    const v1::ComponentDeclaration& component = scene.components(i);
    if (component.name() != bondsName || !component.has_parallel_bonds()) continue;
    const double gap = component.parallel_bonds().gap_tolerance();
    core::requireNonNegative(componentPath(i) + ".parallel_bonds.gap_tolerance", gap);
    return gap;
  }
  throw core::InputError(clodBondsField, "\"" + bondsName + "\"", "no parallel_bonds component has this name");
}

void addClodGroups(ClodGroups& groups, const std::string& bondsName, const core::PitReport& report) {
  auto& group = groups[bondsName];
  std::uint32_t offset = 0;
  for (const auto& [id, clod] : group) offset = std::max(offset, clod);
  for (const auto& [id, clod] : report.clod_members) group.emplace(id, offset + clod);
}

void addParallelBonds(const v1::Scene& scene, const MaterialResolver& resolveMaterial, core::World& world,
                      const ClodGroups& clods) {
  for (int i = 0; i < scene.components_size(); ++i) {
    const v1::ComponentDeclaration& component = scene.components(i);
    if (!component.has_parallel_bonds()) continue;
    const v1::ParallelBonds& bonds = component.parallel_bonds();
    const std::string prefix = componentPath(i) + ".parallel_bonds";
    core::BondRule rule;
    rule.name = component.name();
    core::ParallelBondProperties& p = rule.properties;
    if (bonds.has_radius_multiplier()) p.radius_multiplier = bonds.radius_multiplier();
    p.normal_stiffness_per_area = bonds.normal_stiffness_per_area();
    p.shear_stiffness_per_area = bonds.shear_stiffness_per_area();
    p.tensile_strength = bonds.tensile_strength();
    p.shear_strength = bonds.shear_strength();
    p.gap_tolerance = bonds.gap_tolerance();
    if (bonds.has_fraction()) rule.fraction = bonds.fraction();
    rule.seed = bonds.seed();
    if (bonds.has_region()) {
      TranslatedVolume region = toVolume(bonds.region(), true, world, prefix + ".region");
      rule.region = region.shape;
      rule.placement = region.placement;
    }
    for (int k = 0; k < bonds.materials_size(); ++k) {
      rule.materials.push_back(resolveMaterial(bonds.materials(k), prefix + ".materials[" + std::to_string(k) + "]"));
    }
    if (const auto it = clods.find(component.name()); it != clods.end()) rule.groups = it->second;
    // Time is whole steps (interval_steps.hpp): the bonds are made at the end of step n.
    rule.create_step =
        core::intervalSteps(prefix + ".create_time", bonds.create_time(), world.settings().time_step).steps;
    world.addBondRule(std::move(rule), prefix);
  }
}

}  // namespace demlink::server
