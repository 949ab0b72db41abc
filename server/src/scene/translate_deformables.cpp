/// Deformable body declarations -> engine bodies (contract in translate_deformables.hpp).
///
/// Defaults: an omitted break_force / break_strain never breaks (infinity); an explicit
/// spring without stiffness or damping takes the body's; an omitted rest length is the
/// initial distance (core: rest_length < 0). An attached body's driving reference is the
/// rigid body's reference point at t = 0, whatever driven_reference says.
#include "demlink/server/scene/translate_deformables.hpp"

#include <cmath>
#include <memory>

#include "demlink/core/components/deformable_attachment.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/input_limits.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {
namespace {

using core::InputError;

std::string indexed(const std::string& field, int k) { return field + "[" + std::to_string(k) + "]"; }

/// Nodes of the deformable bodies the world holds already [-].
std::uint64_t deformableNodes(const core::World& world) {
  std::uint64_t nodes = 0;
  for (const auto& body : world.deformableBodies()) nodes += body->nodeCount();
  return nodes;
}

/// lo and hi of a box declaration (`Given`: NodeRegion, MassSpringBox), finite, hi >= lo.
template <class Given, class Box>
void readCorners(const Given& given, const std::string& prefix, Box& out) {
  out.lo = toFiniteVec3(given.lo(), prefix + ".lo");
  out.hi = toFiniteVec3(given.hi(), prefix + ".hi");
  for (int axis = 0; axis < 3; ++axis) {
    if (out.hi[axis] < out.lo[axis]) {
      throw InputError(indexed(prefix + ".hi", axis), core::formatValue(out.hi[axis]),
                       "below lo (" + core::formatValue(out.lo[axis]) + ")");
    }
  }
}

std::vector<core::NodeRegion> regionsOf(const v1::NodeSet& set, const std::string& prefix) {
  std::vector<core::NodeRegion> out;
  for (int k = 0; k < set.regions_size(); ++k) {
    const v1::NodeRegion& region = set.regions(k);
    const std::string field = indexed(prefix + ".regions", k);
    if (!region.has_lo()) throw InputError(field + ".lo", "(missing)", "a node region needs lo and hi");
    if (!region.has_hi()) throw InputError(field + ".hi", "(missing)", "a node region needs lo and hi");
    core::NodeRegion r;
    readCorners(region, field, r);
    out.push_back(r);
  }
  return out;
}

/// Fixed and driven sets, the driving reference; shared by both kinds.
void readConstraints(const v1::NodeSet& fixed, const v1::NodeSet& driven, const v1::Vector3& reference,
                     const std::string& prefix, core::NodeConstraintSpec& spec) {
  spec.fixed_nodes.assign(fixed.nodes().begin(), fixed.nodes().end());
  spec.fixed_regions = regionsOf(fixed, prefix + ".fixed");
  spec.driven_nodes.assign(driven.nodes().begin(), driven.nodes().end());
  spec.driven_regions = regionsOf(driven, prefix + ".driven");
  spec.driven_reference = toFiniteVec3(reference, prefix + ".driven_reference");
}

std::string existingFile(const std::string& path, const FileScope& files,
                         const std::string& field, const std::string& what) {
  return resolveExistingSceneFile(path, files, field, what + " is required").string();
}

double optionalPositive(bool has, double value, const std::string& field, double omitted) {
  if (!has) return omitted;
  core::requirePositive(field, value);
  return value;
}

core::MassSpringSpec::Box boxOf(const v1::MassSpringBox& box, const std::string& prefix) {
  if (!box.has_lo()) throw InputError(prefix + ".lo", "(missing)", "a box needs lo and hi");
  if (!box.has_hi()) throw InputError(prefix + ".hi", "(missing)", "a box needs lo and hi");
  core::MassSpringSpec::Box out;
  readCorners(box, prefix, out);
  core::requirePositive(prefix + ".node_spacing", box.node_spacing());
  out.node_spacing = box.node_spacing();
  return out;
}

void readExplicit(const v1::MassSpringNodes& given, const std::string& prefix, core::MassSpringSpec& spec) {
  if (given.nodes_size() < 2) {
    throw InputError(prefix + ".nodes", std::to_string(given.nodes_size()) + " nodes", "at least two nodes are needed");
  }
  if (given.springs_size() < 1) throw InputError(prefix + ".springs", "0 springs", "at least one spring is needed");
  for (int k = 0; k < given.nodes_size(); ++k) {
    spec.nodes.push_back(toFiniteVec3(given.nodes(k), indexed(prefix + ".nodes", k)));
  }
  const auto nodeCount = static_cast<std::uint32_t>(spec.nodes.size());
  const auto requireNode = [&](std::uint32_t node, const std::string& field) {
    if (node >= nodeCount) {
      throw InputError(field, std::to_string(node), "no such node (" + std::to_string(nodeCount) + " nodes)");
    }
  };
  for (int k = 0; k < given.springs_size(); ++k) {
    const v1::Spring& s = given.springs(k);
    const std::string field = indexed(prefix + ".springs", k);
    requireNode(s.a(), field + ".a");
    requireNode(s.b(), field + ".b");
    if (s.a() == s.b()) throw InputError(field + ".b", std::to_string(s.b()), "a spring joins two different nodes");
    core::SpringSpec spring;
    spring.a = s.a();
    spring.b = s.b();
    spring.stiffness = optionalPositive(s.has_stiffness(), s.stiffness(), field + ".stiffness", spec.stiffness);
    spring.damping = spec.damping;
    if (s.has_damping()) {
      core::requireNonNegative(field + ".damping", s.damping());
      spring.damping = s.damping();
    }
    spring.rest_length = optionalPositive(s.has_rest_length(), s.rest_length(), field + ".rest_length", -1.0);
    spec.springs.push_back(spring);
  }
  for (int k = 0; k < given.triangles_size(); ++k) {
    const v1::NodeTriangle& t = given.triangles(k);
    const std::string field = indexed(prefix + ".triangles", k);
    requireNode(t.a(), field + ".a");
    requireNode(t.b(), field + ".b");
    requireNode(t.c(), field + ".c");
    spec.triangles.push_back({t.a(), t.b(), t.c()});
  }
}

/// The mesh index of `name` among world.meshes(); InputError naming `field` otherwise.
std::size_t attachedMesh(const core::World& world, const std::string& name, const std::string& field) {
  std::string declared;
  for (std::size_t k = 0; k < world.meshes().size(); ++k) {
    if (world.meshes()[k].name() == name) return k;
    declared += (declared.empty() ? "" : ", ") + world.meshes()[k].name();
  }
  throw InputError(field, "\"" + name + "\"",
                   "no rigid_body, facet_body or mesh_body of that name (declared: " +
                       (declared.empty() ? std::string("none") : declared) + ")");
}

}  // namespace

core::MassSpringSpec translateMassSpringBody(const v1::MassSpringBody& body, const std::string& name,
                                             const MaterialResolver& resolveMaterial,
                                             const FileScope& files,
                                             const std::string& fieldPrefix) {
  core::MassSpringSpec spec;
  spec.name = name;
  spec.material = resolveMaterial(body.material(), fieldPrefix + ".material");
  core::requirePositive(fieldPrefix + ".total_mass", body.total_mass());
  spec.total_mass = body.total_mass();
  core::requirePositive(fieldPrefix + ".stiffness", body.stiffness());
  spec.stiffness = body.stiffness();
  core::requireNonNegative(fieldPrefix + ".damping", body.damping());
  spec.damping = body.damping();
  core::requireNonNegative(fieldPrefix + ".shear_factor", body.shear_factor());
  core::requireNonNegative(fieldPrefix + ".bending_factor", body.bending_factor());
  if (!body.has_box() && (body.shear_factor() > 0.0 || body.bending_factor() > 0.0)) {
    throw InputError(fieldPrefix + (body.shear_factor() > 0.0 ? ".shear_factor" : ".bending_factor"),
                     core::formatValue(body.shear_factor() > 0.0 ? body.shear_factor() : body.bending_factor()),
                     "shear and bending springs are built for a box only");
  }
  spec.shear_factor = body.shear_factor();
  spec.bending_factor = body.bending_factor();
  switch (body.geometry_case()) {
    case v1::MassSpringBody::kBox: spec.box = boxOf(body.box(), fieldPrefix + ".box"); break;
    case v1::MassSpringBody::kStlFile:
      spec.stl_path = existingFile(body.stl_file(), files, fieldPrefix + ".stl_file", "an STL file path");
      break;
    case v1::MassSpringBody::kExplicitNodes:
      readExplicit(body.explicit_nodes(), fieldPrefix + ".explicit_nodes", spec);
      break;
    case v1::MassSpringBody::GEOMETRY_NOT_SET:
      throw InputError(fieldPrefix, "\"" + name + "\"", "a mass_spring_body needs box, stl_file or explicit_nodes");
  }
  spec.break_force = optionalPositive(body.has_break_force(), body.break_force(), fieldPrefix + ".break_force",
                                      std::numeric_limits<double>::infinity());
  spec.break_strain = optionalPositive(body.has_break_strain(), body.break_strain(), fieldPrefix + ".break_strain",
                                       std::numeric_limits<double>::infinity());
  readConstraints(body.fixed(), body.driven(), body.driven_reference(), fieldPrefix, spec);
  return spec;
}

core::FemSpec translateFemBody(const v1::FemBody& body, const std::string& name,
                               const MaterialResolver& resolveMaterial, const FileScope& files,
                               const std::string& fieldPrefix) {
  core::FemSpec spec;
  spec.name = name;
  spec.material = resolveMaterial(body.material(), fieldPrefix + ".material");
  switch (body.integrator()) {
    case v1::FemBody::INTEGRATOR_UNSPECIFIED:
    case v1::FemBody::THREE_LEVEL: spec.integrator = core::FemIntegrator::kThreeLevel; break;
    case v1::FemBody::CENTRAL_DIFFERENCE: spec.integrator = core::FemIntegrator::kCentralDifference; break;
    default:
      throw InputError(fieldPrefix + ".integrator", std::to_string(body.integrator()), "unknown integrator");
  }
  core::requireNonNegative(fieldPrefix + ".rayleigh_alpha", body.rayleigh_alpha());
  core::requireNonNegative(fieldPrefix + ".rayleigh_beta", body.rayleigh_beta());
  spec.rayleigh_alpha = body.rayleigh_alpha();
  spec.rayleigh_beta = body.rayleigh_beta();
  switch (body.source_case()) {
    case v1::FemBody::kMesh: {
      const v1::FemMesh& mesh = body.mesh();
      const std::string prefix = fieldPrefix + ".mesh";
      spec.msh_path = existingFile(mesh.msh_file(), files, prefix + ".msh_file", "a Gmsh .msh file path");
      core::requirePositive(prefix + ".youngs_modulus", mesh.youngs_modulus());
      core::requireOpenRange(prefix + ".poisson_ratio", mesh.poisson_ratio(), -1.0, 0.5);
      core::requirePositive(prefix + ".density", mesh.density());
      spec.youngs_modulus = mesh.youngs_modulus();
      spec.poisson_ratio = mesh.poisson_ratio();
      spec.density = mesh.density();
      switch (mesh.mass()) {
        case v1::FemMesh::MASS_UNSPECIFIED:
        case v1::FemMesh::LUMPED: spec.mass = core::FemMass::kLumped; break;
        case v1::FemMesh::CONSISTENT: spec.mass = core::FemMass::kConsistent; break;
        default: throw InputError(prefix + ".mass", std::to_string(mesh.mass()), "unknown mass matrix kind");
      }
      spec.offset = toFiniteVec3(mesh.offset(), prefix + ".offset");
      break;
    }
    case v1::FemBody::kMatrices: {
      const v1::FemMatrices& m = body.matrices();
      const std::string prefix = fieldPrefix + ".matrices";
      spec.mass_matrix_path =
          existingFile(m.mass_matrix_file(), files, prefix + ".mass_matrix_file", "a Matrix Market file");
      spec.stiffness_matrix_path = existingFile(m.stiffness_matrix_file(), files,
                                                prefix + ".stiffness_matrix_file", "a Matrix Market file");
      if (!m.damping_matrix_file().empty()) {
        spec.damping_matrix_path = existingFile(m.damping_matrix_file(), files,
                                                prefix + ".damping_matrix_file", "a Matrix Market file");
      }
      spec.nodes_path = existingFile(m.nodes_file(), files, prefix + ".nodes_file", "a node file");
      spec.triangles_path =
          existingFile(m.triangles_file(), files, prefix + ".triangles_file", "a triangle file");
      break;
    }
    case v1::FemBody::SOURCE_NOT_SET:
      throw InputError(fieldPrefix, "\"" + name + "\"", "an fem_body needs mesh or matrices");
  }
  readConstraints(body.fixed(), body.driven(), body.driven_reference(), fieldPrefix, spec);
  return spec;
}

void addDeformableBodies(const v1::Scene& scene, const MaterialResolver& resolveMaterial,
                         const FileScope& files, core::World& world) {
  for (int i = 0; i < scene.components_size(); ++i) {
    const v1::ComponentDeclaration& component = scene.components(i);
    const std::string path = componentPath(i);
    // An attached body's reference is the mesh's reference point at t = 0.
    std::optional<std::size_t> mesh;
    const auto attach = [&](const std::string& attachedTo, const std::string& prefix, core::Vec3& reference) {
      if (attachedTo.empty()) return;
      mesh = attachedMesh(world, attachedTo, prefix + ".attached_to");
      reference = world.meshes()[*mesh].position();
    };
    std::unique_ptr<core::DeformableBody> body;
    std::string prefix;
    if (component.has_mass_spring_body()) {
      prefix = path + ".mass_spring_body";
      core::MassSpringSpec spec = translateMassSpringBody(component.mass_spring_body(), component.name(),
                                                          resolveMaterial, files, prefix);
      attach(component.mass_spring_body().attached_to(), prefix, spec.driven_reference);
      if (spec.box) {
        // Refused before the lattice is built: a node with its springs costs about a sphere.
        const double nodes = spec.box->nodeCount();
        if (nodes > 1e15) {
          throw InputError(prefix + ".box.node_spacing", core::formatValue(spec.box->node_spacing),
                           "gives more than 1e15 nodes");
        }
        requireParticleMemory(prefix + ".box.node_spacing", core::formatValue(spec.box->node_spacing),
                              world.particles().size() + deformableNodes(world) + static_cast<std::uint64_t>(nodes));
      }
      body = std::make_unique<core::MassSpringBody>(spec, prefix);
    } else if (component.has_fem_body()) {
      prefix = path + ".fem_body";
      core::FemSpec spec =
          translateFemBody(component.fem_body(), component.name(), resolveMaterial, files, prefix);
      attach(component.fem_body().attached_to(), prefix, spec.driven_reference);
      body = std::make_unique<core::FemBody>(spec, world.settings().time_step, prefix);
    } else {
      continue;
    }
    const std::size_t index = world.deformableBodies().size();
    world.addDeformableBody(std::move(body), prefix);
    if (mesh) world.addComponent(std::make_unique<core::DeformableAttachment>(component.name(), index, *mesh));
  }
}

std::vector<std::uint32_t> outputNodesOf(const v1::DeformableOutputNodes& declared, std::size_t nodeCount,
                                         std::size_t surfaceCount, const std::string& field) {
  std::vector<std::uint32_t> out;
  if (declared.nodes_size() > 0) {
    for (int k = 0; k < declared.nodes_size(); ++k) {
      if (declared.nodes(k) >= nodeCount) {
        throw InputError(indexed(field + ".nodes", k), std::to_string(declared.nodes(k)),
                         "no such node (" + std::to_string(nodeCount) + " nodes)");
      }
      out.push_back(declared.nodes(k));
    }
    return out;
  }
  const std::size_t maxCount = declared.max_count() > 0 ? declared.max_count() : 10000;
  const std::size_t stride = std::max<std::size_t>(1, (surfaceCount + maxCount - 1) / maxCount);
  for (std::size_t node = 0; node < surfaceCount; node += stride) out.push_back(static_cast<std::uint32_t>(node));
  return out;
}

}  // namespace demlink::server
