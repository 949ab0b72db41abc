/// LIGGGHTS input of a compiled scene (contract in liggghts_script.hpp).
#include "demlink/server/backend/liggghts_script.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <tuple>

#include "demlink/core/particles/sphere.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {
namespace {

using Kind = v1::ComponentDeclaration::KindCase;

/// Why a component kind cannot run on LIGGGHTS-PUBLIC; empty if it can.
std::string refusalReason(Kind kind) {
  switch (kind) {
    case Kind::kClumpTemplate:
      return "LIGGGHTS-PUBLIC has no multisphere clumps (fix multisphere is in the premium version only)";
    case Kind::kMassSpringBody:
    case Kind::kFemBody:
      return "LIGGGHTS has no deformable bodies";
    case Kind::kParallelBonds:
      return "LIGGGHTS-PUBLIC has no parallel bonds";
    default:
      return {};
  }
}

/// What of a component the LIGGGHTS backend cannot run although it maps its kind: a facet
/// body that is not FIXED or has a collision window, a pit generator of clumps. Throws
/// core::InputError naming the field.
void refuseUnmappedFields(const v1::ComponentDeclaration& component, const std::string& field) {
  const std::string reason = "; run it on the native backend";
  if (component.has_facet_body()) {
    const v1::FacetBody& facet = component.facet_body();
    const v1::FacetBody::Role role = facet.role();
    if (role != v1::FacetBody::FIXED && role != v1::FacetBody::ROLE_UNSPECIFIED) {
      throw core::InputError(field + ".role", v1::FacetBody::Role_Name(role),
                             "facet body " + component.name() + ": only FIXED facet bodies are mapped to LIGGGHTS (a "
                             "mesh at rest); role " + v1::FacetBody::Role_Name(role) + " is not" + reason);
    }
    for (const auto& [given, name, value] :
         {std::tuple{facet.has_active_from(), ".active_from", facet.active_from()},
          std::tuple{facet.has_active_until(), ".active_until", facet.active_until()}}) {
      if (given) {
        throw core::InputError(field + name, core::formatValue(value),
                               "facet body " + component.name() + ": LIGGGHTS's walls cannot be switched on or off "
                               "in time" + reason);
      }
    }
  }
  if (component.has_tracker() && component.tracker().nodes_size() > 0) {
    throw core::InputError(field + ".nodes[0]", component.tracker().nodes(0),
                           "tracker " + component.name() + ": LIGGGHTS has no deformable bodies, so no nodes to track" +
                               reason);
  }
  if (component.has_pit_generator() && !component.pit_generator().clump_template().empty()) {
    throw core::InputError(field + ".clump_template", component.pit_generator().clump_template(),
                           "pit generator " + component.name() + ": LIGGGHTS-PUBLIC has no multisphere clumps" + reason);
  }
}

/// The axis (0, 1, 2) a plane's normal lies along, or -1.
int planeAxis(const core::Vec3& normal) {
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(std::abs(normal[axis]) - 1.0) < 1.0e-12) return axis;
  }
  return -1;
}

void refuseIf(bool refused, const std::string& field, const std::string& value, const std::string& reason) {
  if (refused) throw core::InputError(field, value, reason);
}

std::string joined(const std::vector<double>& values) {
  std::string text;
  for (double value : values) text += fmt::format(" {:.17g}", value);
  return text;
}

}  // namespace

std::string liggghtsMeshFix(std::size_t mesh) { return fmt::format("demlink_mesh{}", mesh); }

double liggghtsRestitution(double normalDamping, const std::string& field) {
  // beta = -c / (2 sqrt(5/6)); ln e = beta pi / sqrt(1 - beta^2).
  const double beta = -normalDamping / (2.0 * std::sqrt(5.0 / 6.0));
  refuseIf(!(normalDamping >= 0.0) || !(beta > -1.0), field, core::formatValue(normalDamping),
           "no LIGGGHTS restitution gives this damping (restitution too low for LIGGGHTS's Hertz law)");
  return std::exp(beta * std::numbers::pi / std::sqrt(1.0 - beta * beta));
}

void requireLiggghtsCompatible(const v1::Scene& scene, const core::World& world) {
  std::string box = "simulation_box";
  for (int i = 0; i < scene.components_size(); ++i) {
    const v1::ComponentDeclaration& component = scene.components(i);
    const std::string field = componentPath(i) + "." + componentKindName(component.kind_case());
    const std::string reason = refusalReason(component.kind_case());
    refuseIf(!reason.empty(), field, component.name(), reason + "; run it on the native backend");
    refuseUnmappedFields(component, field);
    if (component.has_simulation_box()) box = componentPath(i) + ".simulation_box";
  }
  const core::SimulationSettings& settings = world.settings();
  refuseIf(!settings.frame.isInertial(), box + ".frame", "moving room",
           "LIGGGHTS has no fictitious forces of a moving room; run it on the native backend");
  refuseIf(settings.contact_model != core::ContactModel::HertzMindlin, box + ".contact_model",
           std::string(core::toString(settings.contact_model)),
           "the LIGGGHTS backend maps the Hertz-Mindlin law only");
  refuseIf(settings.integrator != core::IntegratorKind::VelocityVerlet, box + ".integrator", "EXPLICIT_EULER",
           "LIGGGHTS integrates with velocity Verlet (fix nve/sphere) only");
  refuseIf(!settings.bounds, box + ".bounds", "none", "LIGGGHTS needs a fixed box; declare simulation_box.bounds");
  refuseIf(settings.bounds && settings.bounds->growing, box + ".bounds.mode", "GROWING",
           "LIGGGHTS's box does not grow; declare fixed bounds");
  for (std::uint32_t m = 0; m < world.materials().size(); ++m) {
    const core::Material& material = world.materials()[m];
    refuseIf(material.cohesion_energy_density > 0.0, "material " + material.name + ".cohesion_energy_density",
             core::formatValue(material.cohesion_energy_density),
             "cohesion is not mapped by the LIGGGHTS backend (its cohesion models differ from ours)");
  }
  refuseIf(world.pairTable().anyCohesion(), "material_pair.cohesion_energy_density", "> 0",
           "cohesion is not mapped by the LIGGGHTS backend (its cohesion models differ from ours)");
  for (const core::PlaneWall& plane : world.planes()) {
    refuseIf(planeAxis(plane.spec.normal) < 0, "plane " + plane.spec.name + ".normal",
             fmt::format("({}, {}, {})", plane.spec.normal.x(), plane.spec.normal.y(), plane.spec.normal.z()),
             "LIGGGHTS primitive walls are axis-aligned; tilted planes are not mapped");
  }
}

std::string liggghtsDataFile(const core::World& world) {
  const core::ParticleArrays& p = world.particles();
  const core::DomainBounds bounds = world.settings().bounds.value_or(core::DomainBounds{});
  std::string text = "DEMLink scene for LIGGGHTS\n\n";
  text += fmt::format("{} atoms\n{} atom types\n\n", p.size(), world.materials().size());
  const char* axes[] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    text += fmt::format("{:.17g} {:.17g} {}lo {}hi\n", bounds.lower[axis], bounds.upper[axis], axes[axis], axes[axis]);
  }
  if (p.size() == 0) return text;
  text += "\nAtoms\n\n";
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = p.radius[i];
    const double density = p.mass[i] / core::sphereVolume(r);
    text += fmt::format("{} {} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", i + 1, p.material[i] + 1, 2.0 * r, density,
                        p.position[i].x(), p.position[i].y(), p.position[i].z());
  }
  text += "\nVelocities\n\n";
  for (std::size_t i = 0; i < p.size(); ++i) {
    const core::Vec3& v = p.velocity[i];
    const core::Vec3& w = p.angular_velocity[i];
    text += fmt::format("{} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", i + 1, v.x(), v.y(), v.z(), w.x(),
                        w.y(), w.z());
  }
  return text;
}

std::string liggghtsStl(const core::MeshBody& mesh) {
  const std::vector<core::Vec3>& x = mesh.worldVertices();
  std::string text = fmt::format("solid {}\n", mesh.name());
  for (const auto& triangle : mesh.triangles()) {
    text += " facet normal 0 0 0\n  outer loop\n";
    for (std::uint32_t corner : triangle) {
      text += fmt::format("   vertex {:.17g} {:.17g} {:.17g}\n", x[corner].x(), x[corner].y(), x[corner].z());
    }
    text += "  endloop\n endfacet\n";
  }
  text += fmt::format("endsolid {}\n", mesh.name());
  return text;
}

std::vector<std::string> liggghtsCommands(const core::World& world, const std::string& dataFile,
                                          const std::vector<std::string>& meshFiles, const std::string& restartFile) {
  if (meshFiles.size() != world.meshes().size()) {
    throw std::invalid_argument("liggghtsCommands: one STL file per mesh expected");
  }
  const std::vector<core::Material>& materials = world.materials();
  const std::size_t types = materials.size();
  double stiffest = 0.0;
  for (const core::Material& material : materials) stiffest = std::max(stiffest, material.youngs_modulus);
  std::vector<double> youngs;
  std::vector<double> poisson;
  for (const core::Material& material : materials) {
    youngs.push_back(material.rigid ? 1.0e6 * stiffest : material.youngs_modulus);
    poisson.push_back(material.poisson_ratio);
  }
  std::vector<double> restitution;
  std::vector<double> friction;
  std::vector<double> rolling;
  const core::ContactPairTable& table = world.pairTable();
  for (std::uint32_t a = 0; a < types; ++a) {
    for (std::uint32_t b = 0; b < types; ++b) {
      if (table.covers(a) && table.covers(b)) {
        const core::ContactPairParams& pair = table(a, b);
        restitution.push_back(liggghtsRestitution(
            pair.normal_damping, "material pair " + materials[a].name + " / " + materials[b].name + ".restitution"));
        friction.push_back(pair.sliding_friction);
        rolling.push_back(pair.rolling_friction);
      } else {  // no contact of this pair can occur; LIGGGHTS still wants a value
        restitution.push_back(0.5);
        friction.push_back(0.5 * (materials[a].sliding_friction + materials[b].sliding_friction));
        rolling.push_back(0.0);
      }
    }
  }
  // Our rolling resistance is a constant directional torque (docs/physics.md): LIGGGHTS's
  // rolling_friction cdt, in the particle pairs and at every wall. Our normal force never
  // pulls (clamped at zero, and the restitution is calibrated with the clamp); LIGGGHTS's
  // Hertz law lets the damping pull at the end of a contact unless limitForce is on, which
  // with our damping delivers e = 0.436 where ours delivers 0.5 (docs/scale-out.md). A
  // wall/gran fix takes the model's settings after its wall arguments.
  const std::string law = std::string("model hertz tangential history") +
                          (table.anyRollingFriction() ? " rolling_friction cdt" : "");
  const std::string neverPulls = "limitForce on";
  const std::string pairStyle = "pair_style gran " + law + " " + neverPulls;
  std::vector<std::string> commands = {
      "units si",
      "atom_style granular",
      "atom_modify map array",
      "boundary f f f",
      "newton off",
      "communicate single vel yes",
      fmt::format("neighbor {:.17g} bin", world.neighbourSkin()),
      "neigh_modify delay 0",
      "fix demlink_youngs all property/global youngsModulus peratomtype" + joined(youngs),
      "fix demlink_poisson all property/global poissonsRatio peratomtype" + joined(poisson),
      fmt::format("fix demlink_restitution all property/global coefficientRestitution peratomtypepair {}{}", types,
                  joined(restitution)),
      fmt::format("fix demlink_friction all property/global coefficientFriction peratomtypepair {}{}", types,
                  joined(friction)),
      pairStyle,
      "pair_coeff * *",
      fmt::format("timestep {:.17g}", world.settings().time_step),
  };
  // Ranks split the box across gravity, never along it: a bed settles flat, and a split
  // along gravity leaves the ranks above it nothing to do (docs/scale-out.md "Benchmark").
  if (const core::Vec3 g = world.gravity().cwiseAbs(); g.maxCoeff() > 0.0) {
    Eigen::Index down = 0;
    g.maxCoeff(&down);
    const char* grids[] = {"processors 1 * *", "processors * 1 *", "processors * * 1"};
    commands.insert(std::find(commands.begin(), commands.end(), "boundary f f f") + 1, grids[down]);
  }
  if (table.anyRollingFriction()) {
    commands.insert(std::find(commands.begin(), commands.end(), pairStyle),
                    fmt::format("fix demlink_rolling all property/global coefficientRollingFriction peratomtypepair {}{}",
                                types, joined(rolling)));
  }
  // A scene that starts empty (filled by sources) gets its box from create_box: LIGGGHTS's
  // read_data of no atoms leaves the atoms without ids (no atom map then).
  const auto created = std::find(commands.begin(), commands.end(), "communicate single vel yes") + 1;
  if (!restartFile.empty()) {
    commands.insert(created, "read_restart " + restartFile);
  } else if (world.particles().size() > 0) {
    commands.insert(created, "read_data " + dataFile);
  } else {
    const core::DomainBounds bounds = world.settings().bounds.value_or(core::DomainBounds{});
    commands.insert(created, {fmt::format("region demlink_domain block {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} "
                                          "units box",
                                          bounds.lower.x(), bounds.upper.x(), bounds.lower.y(), bounds.upper.y(),
                                          bounds.lower.z(), bounds.upper.z()),
                              fmt::format("create_box {} demlink_domain", types)});
  }
  const core::Vec3 gravity = world.gravity();
  if (gravity.norm() > 0.0) {
    const core::Vec3 direction = gravity.normalized();
    commands.push_back(fmt::format("fix demlink_gravity all gravity {:.17g} vector {:.17g} {:.17g} {:.17g}",
                                   gravity.norm(), direction.x(), direction.y(), direction.z()));
  }
  const char* planeNames[] = {"xplane", "yplane", "zplane"};
  for (std::size_t k = 0; k < world.planes().size(); ++k) {
    const core::PlaneSpec& plane = world.planes()[k].spec;
    const int axis = planeAxis(plane.normal);
    if (axis < 0) throw core::InputError("plane " + plane.name + ".normal", "tilted", "not axis-aligned");
    commands.push_back(fmt::format("fix demlink_plane{} all wall/gran {} primitive type {} {} {:.17g} {}", k, law,
                                   plane.material + 1, planeNames[axis], plane.point[axis], neverPulls));
  }
  std::string meshIds;
  for (std::size_t k = 0; k < world.meshes().size(); ++k) {
    const core::MeshBody& mesh = world.meshes()[k];
    const core::Vec3& reference = mesh.position();
    commands.push_back(fmt::format("fix {} all mesh/surface/stress file {} type {} reference_point {:.17g} {:.17g} {:.17g}",
                                   liggghtsMeshFix(k), meshFiles[k], mesh.materialIndex() + 1, reference.x(),
                                   reference.y(), reference.z()));
    meshIds += fmt::format(" {}", liggghtsMeshFix(k));
  }
  if (!world.meshes().empty()) {
    commands.push_back(
        fmt::format("fix demlink_meshes all wall/gran {} mesh n_meshes {} meshes{} {}", law, world.meshes().size(),
                    meshIds, neverPulls));
  }
  commands.push_back("fix demlink_integrate all nve/sphere");
  commands.push_back("thermo_modify lost ignore norm no");
  return commands;
}

}  // namespace demlink::server
