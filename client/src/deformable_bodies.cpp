/// MassSpringBody and FemBody: declaration setters, the persistent driven pose and the outputs.
#include "demlink/client/deformable_bodies.hpp"

#include <stdexcept>
#include <utility>

#include "demlink/v1/protocol.pb.h"

namespace demlink::client {

namespace {

/// Calls `f` with the declared MassSpringBody or FemBody message (same field names).
template <class F>
void withBody(v1::ComponentDeclaration& declaration, F&& f) {
  if (declaration.has_mass_spring_body()) {
    f(*declaration.mutable_mass_spring_body());
  } else {
    f(*declaration.mutable_fem_body());
  }
}

}  // namespace

void DeformableBody::declareMaterial(const std::string& material) {
  withBody(declaration(), [&](auto& body) { body.set_material(material); });
}

void DeformableBody::declareRegion(bool driven, const Vec3& lo, const Vec3& hi) {
  withBody(declaration(), [&](auto& body) {
    v1::NodeRegion& region = *(driven ? body.mutable_driven() : body.mutable_fixed())->add_regions();
    *region.mutable_lo() = toProto(lo);
    *region.mutable_hi() = toProto(hi);
  });
}

void DeformableBody::declareDrivenReference(const Vec3& point) {
  withBody(declaration(), [&](auto& body) { *body.mutable_driven_reference() = toProto(point); });
}

void DeformableBody::declareAttachedTo(const std::string& rigidBody) {
  withBody(declaration(), [&](auto& body) { body.set_attached_to(rigidBody); });
}

void DeformableBody::declareOutputNodes(const std::vector<std::uint32_t>& nodes) {
  withBody(declaration(), [&](auto& body) { body.mutable_output_nodes()->mutable_nodes()->Assign(nodes.begin(), nodes.end()); });
}

void DeformableBody::setDrivenPose(const Vec3& position, const Quat& orientation) {
  if (!input_) input_.reset(new v1::DeformableBodyInput());
  *input_->mutable_position() = toProto(position);
  *input_->mutable_orientation() = toProto(orientation);
  pose_set_ = true;
}

void DeformableBody::setDrivenVelocity(const Vec3& linear, const Vec3& angular) {
  if (!input_) input_.reset(new v1::DeformableBodyInput());
  *input_->mutable_linear_velocity() = toProto(linear);
  *input_->mutable_angular_velocity() = toProto(angular);
}

void DeformableBody::writeInputs(v1::DataPackage& package) const {
  if (pose_set_) *package.mutable_deformable_body_input() = *input_;
}

std::vector<std::uint32_t> DeformableBody::nodes() const {
  const auto& nodes = outputs().deformable_body().nodes();
  return {nodes.begin(), nodes.end()};
}

std::vector<Vec3> DeformableBody::displacements() const {
  const auto& u = outputs().deformable_body().displacements();
  std::vector<Vec3> out;
  for (int k = 0; k + 2 < u.size(); k += 3) out.push_back({u[k], u[k + 1], u[k + 2]});
  return out;
}

Vec3 DeformableBody::displacement(std::size_t k) const {
  const auto& u = outputs().deformable_body().displacements();
  if (3 * k + 2 >= static_cast<std::size_t>(u.size())) {
    throw std::out_of_range("displacement(" + std::to_string(k) + "): " + std::to_string(u.size() / 3) +
                            " nodes reported");
  }
  const int i = static_cast<int>(3 * k);
  return {u[i], u[i + 1], u[i + 2]};
}

Vec3 DeformableBody::drivenForce() const { return fromProto(outputs().deformable_body().driven_force()); }
Vec3 DeformableBody::drivenTorque() const { return fromProto(outputs().deformable_body().driven_torque()); }
Vec3 DeformableBody::fixedForce() const { return fromProto(outputs().deformable_body().fixed_force()); }
Vec3 DeformableBody::fixedTorque() const { return fromProto(outputs().deformable_body().fixed_torque()); }
std::uint64_t DeformableBody::brokenSprings() const { return outputs().deformable_body().broken_springs(); }
double DeformableBody::kineticEnergy() const { return outputs().deformable_body().kinetic_energy(); }
std::uint64_t DeformableBody::nodeCount() const { return outputs().deformable_body().node_count(); }

MassSpringBody::MassSpringBody(std::string name) : DeformableBodyOf(std::move(name)) {
  declaration().mutable_mass_spring_body();
}
MassSpringBody& MassSpringBody::setBox(const Vec3& lo, const Vec3& hi, double nodeSpacing) {
  v1::MassSpringBox& box = *message().mutable_box();
  *box.mutable_lo() = toProto(lo);
  *box.mutable_hi() = toProto(hi);
  box.set_node_spacing(nodeSpacing);
  return *this;
}
MassSpringBody& MassSpringBody::setStlFile(const std::string& pathOnServer) {
  message().set_stl_file(pathOnServer);
  return *this;
}
MassSpringBody& MassSpringBody::setSprings(double totalMass, double stiffness, double damping) {
  message().set_total_mass(totalMass);
  message().set_stiffness(stiffness);
  message().set_damping(damping);
  return *this;
}
MassSpringBody& MassSpringBody::setBreakLimits(double force, double strain) {
  message().set_break_force(force);
  message().set_break_strain(strain);
  return *this;
}

FemBody::FemBody(std::string name) : DeformableBodyOf(std::move(name)) { declaration().mutable_fem_body(); }
FemBody& FemBody::setMesh(const std::string& mshPathOnServer, double youngsModulus, double poissonRatio,
                          double density) {
  v1::FemMesh& mesh = *message().mutable_mesh();
  mesh.set_msh_file(mshPathOnServer);
  mesh.set_youngs_modulus(youngsModulus);
  mesh.set_poisson_ratio(poissonRatio);
  mesh.set_density(density);
  return *this;
}
FemBody& FemBody::setRayleigh(double alpha, double beta) {
  message().set_rayleigh_alpha(alpha);
  message().set_rayleigh_beta(beta);
  return *this;
}

v1::MassSpringBody& MassSpringBody::message() { return *declaration().mutable_mass_spring_body(); }
v1::FemBody& FemBody::message() { return *declaration().mutable_fem_body(); }

}  // namespace demlink::client
