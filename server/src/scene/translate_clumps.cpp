/// Clump templates and clump lattices (translate_clumps.hpp).
///
/// Why the lattice reuses generateLattice: the points (and their jitter) stay
/// exactly those of a sphere lattice with the same seed; only the sphere radius
/// is replaced by the template's bounding radius in the spacing check. The
/// orientations come from their own generator (orientation_seed), one uniform
/// rotation per point in lattice order, so changing them never moves the points.
#include "demlink/server/scene/translate_clumps.hpp"

#include <vector>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/server/scene/input_limits.hpp"
#include "demlink/core/base/random.hpp"
#include "demlink/server/scene/particle_lattice.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {

using core::InputError;

void addClumpTemplates(const v1::Scene& scene, core::World& world) {
  for (int i = 0; i < scene.components_size(); ++i) {
    const v1::ComponentDeclaration& component = scene.components(i);
    if (!component.has_clump_template()) continue;
    const std::string prefix = componentPath(i) + ".clump_template";
    std::vector<core::ClumpSphere> spheres;
    for (const v1::ClumpSphere& sphere : component.clump_template().spheres()) {
      spheres.push_back({core::Vec3(sphere.offset().x(), sphere.offset().y(), sphere.offset().z()), sphere.radius()});
    }
    world.addClumpTemplate(core::ClumpTemplate(component.name(), std::move(spheres), prefix), prefix);
  }
}

void addClumpLattice(const v1::ParticleLattice& lattice, std::uint32_t material, const std::string& prefix,
                     core::World& world) {
  const std::string& name = lattice.clump_template();
  const std::optional<std::uint32_t> index = world.findClumpTemplate(name);
  if (!index) {
    std::string declared;
    for (const core::ClumpTemplate& shape : world.clumpTemplates()) {
      declared += (declared.empty() ? "" : ", ") + shape.name();
    }
    throw InputError(prefix + ".clump_template", core::quotedLogText(name),
                     "unknown clump template (declared: " + (declared.empty() ? "none" : declared) + ")");
  }
  if (lattice.radius() != 0.0) {
    throw InputError(prefix + ".radius", core::formatValue(lattice.radius()),
                     "must be omitted when clump_template is set (the template sets the size)");
  }
  if (lattice.has_radius_max()) {
    throw InputError(prefix + ".radius_max", core::formatValue(lattice.radius_max()),
                     "must be omitted when clump_template is set (the template sets the size)");
  }
  const core::ClumpTemplate& shape = world.clumpTemplates()[*index];
  LatticeSpec spec;
  spec.material = material;
  spec.radius = shape.boundingRadius();
  spec.origin = core::Vec3(lattice.origin().x(), lattice.origin().y(), lattice.origin().z());
  spec.spacing = lattice.spacing();
  if (!lattice.has_counts()) throw InputError(prefix + ".counts", "(missing)", "required (nx, ny, nz)");
  spec.counts = {lattice.counts().nx(), lattice.counts().ny(), lattice.counts().nz()};
  spec.jitter = lattice.jitter();
  spec.seed = lattice.seed();
  spec.velocity = core::Vec3(lattice.velocity().x(), lattice.velocity().y(), lattice.velocity().z());
  core::requireNonNegative(prefix + ".jitter", spec.jitter);
  core::requirePositive(prefix + ".spacing", spec.spacing);
  if (!(spec.spacing > 2.0 * (spec.radius + spec.jitter))) {
    throw InputError(prefix + ".spacing", core::formatValue(spec.spacing),
                     "must exceed 2 (bounding radius of clump template \"" + name + "\" + jitter) = " +
                         core::formatValue(2.0 * (spec.radius + spec.jitter)) + " m, or neighbouring clumps could overlap");
  }
  spec.validate(prefix);
  requireParticleMemory(prefix + ".counts", spec.countText(),
                        world.particles().size() + spec.count() * shape.bodySpheres().size());
  core::Random rng(lattice.orientation_seed());
  for (const core::ParticleSpec& point : generateLattice(spec)) {
    core::ClumpSpec clump;
    clump.template_index = *index;
    clump.material = material;
    clump.position = point.position;
    clump.velocity = point.velocity;
    clump.orientation = core::uniformRotation(rng);
    world.addClump(clump, prefix);
  }
}

}  // namespace demlink::server
