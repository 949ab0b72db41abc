/// Typed setters and output getters of the scene-setup components. Getters read the
/// latest package's oneof and give zeros before the first one, so a model can plot them
/// from t = 0 without special cases.
#include "demlink/client/scene_components.hpp"

#include <utility>

#include "demlink/v1/protocol.pb.h"

namespace demlink::client {

SimulationBox::SimulationBox(std::string name) : Component(std::move(name)) {
  declaration().mutable_simulation_box();
}
SimulationBox& SimulationBox::setTimeStep(double seconds) {
  message().set_time_step(seconds);
  return *this;
}
SimulationBox& SimulationBox::setEndTime(double seconds) {
  message().set_end_time(seconds);
  return *this;
}
SimulationBox& SimulationBox::setInitialGravity(const Vec3& g) {
  *message().mutable_gravity() = toProto(g);
  return *this;
}
SimulationBox& SimulationBox::setBounds(const Vec3& lower, const Vec3& upper) {
  *message().mutable_bounds()->mutable_lower() = toProto(lower);
  *message().mutable_bounds()->mutable_upper() = toProto(upper);
  return *this;
}
SimulationBox& SimulationBox::setRestitutionTolerance(double tolerance) {
  message().set_restitution_tolerance(tolerance);
  return *this;
}
SimulationBox& SimulationBox::setExpectedCount(std::uint32_t count) {
  message().mutable_coupling()->set_expected_count(count);
  return *this;
}
SimulationBox& SimulationBox::addExpectedName(const std::string& name) {
  message().mutable_coupling()->add_expected_names(name);
  return *this;
}
SimulationBox& SimulationBox::setClientTimeout(double seconds) {
  message().mutable_coupling()->set_client_timeout(seconds);
  return *this;
}
SimulationBox& SimulationBox::setOutputDirectory(const std::string& directory) {
  message().mutable_output()->set_directory(directory);
  return *this;
}

void SimulationBox::setGravity(const Vec3& g) {
  if (!pending_) pending_.reset(new v1::SimulationBoxInput());
  *pending_->mutable_gravity() = toProto(g);
}

void SimulationBox::setFrame(const Vec3& linearAcceleration, const Vec3& angularVelocity,
                             const Vec3& angularAcceleration, const Vec3& origin) {
  if (!pending_) pending_.reset(new v1::SimulationBoxInput());
  auto* frame = pending_->mutable_frame();
  *frame->mutable_linear_acceleration() = toProto(linearAcceleration);
  *frame->mutable_angular_velocity() = toProto(angularVelocity);
  *frame->mutable_angular_acceleration() = toProto(angularAcceleration);
  *frame->mutable_origin() = toProto(origin);
}

void SimulationBox::writeInputs(v1::DataPackage& package) const {
  if (pending_) *package.mutable_simulation_box_input() = *pending_;
}

double SimulationBox::time() const { return outputs().simulation_box().time(); }
std::uint64_t SimulationBox::particleCount() const { return outputs().simulation_box().particle_count(); }
double SimulationBox::totalMass() const { return outputs().simulation_box().total_mass(); }
double SimulationBox::kineticEnergy() const { return outputs().simulation_box().kinetic_energy(); }
double SimulationBox::stepRate() const { return outputs().simulation_box().step_rate(); }

Material::Material(std::string name) : Component(std::move(name)) { declaration().mutable_material(); }
Material& Material::setDatabaseName(const std::string& name) {
  message().set_database_name(name);
  return *this;
}
Material& Material::setDensity(double kgPerM3) {
  message().set_density(kgPerM3);
  return *this;
}
Material& Material::setYoungsModulus(double pascal) {
  message().set_youngs_modulus(pascal);
  return *this;
}
Material& Material::setPoissonRatio(double ratio) {
  message().set_poisson_ratio(ratio);
  return *this;
}
Material& Material::setRestitution(double coefficient) {
  message().set_restitution(coefficient);
  return *this;
}
Material& Material::setSlidingFriction(double coefficient) {
  message().set_sliding_friction(coefficient);
  return *this;
}
Material& Material::setRollingFriction(double coefficient) {
  message().set_rolling_friction(coefficient);
  return *this;
}

Plane::Plane(std::string name) : Component(std::move(name)) { declaration().mutable_plane(); }
Plane& Plane::setPoint(const Vec3& point) {
  *message().mutable_point() = toProto(point);
  return *this;
}
Plane& Plane::setNormal(const Vec3& normal) {
  *message().mutable_normal() = toProto(normal);
  return *this;
}
Plane& Plane::setMaterial(const std::string& material) {
  message().set_material(material);
  return *this;
}

SingleParticle::SingleParticle(std::string name) : Component(std::move(name)) {
  declaration().mutable_single_particle();
}
SingleParticle& SingleParticle::setMaterial(const std::string& material) {
  message().set_material(material);
  return *this;
}
SingleParticle& SingleParticle::setPosition(const Vec3& centre) {
  *message().mutable_position() = toProto(centre);
  return *this;
}
SingleParticle& SingleParticle::setVelocity(const Vec3& velocity) {
  *message().mutable_velocity() = toProto(velocity);
  return *this;
}
SingleParticle& SingleParticle::setAngularVelocity(const Vec3& omega) {
  *message().mutable_angular_velocity() = toProto(omega);
  return *this;
}
SingleParticle& SingleParticle::setDiameter(double metres) {
  message().set_diameter(metres);
  return *this;
}

ParticleSystem::ParticleSystem(std::string name) : Component(std::move(name)) {
  declaration().mutable_particle_system();
}
ParticleSystem& ParticleSystem::setCsvFile(const std::string& path) {
  message().set_csv_file(path);
  return *this;
}
ParticleSystem& ParticleSystem::setCheckpointFile(const std::string& path) {
  message().set_checkpoint_file(path);
  return *this;
}

v1::SimulationBox& SimulationBox::message() { return *declaration().mutable_simulation_box(); }
v1::Material& Material::message() { return *declaration().mutable_material(); }
v1::Plane& Plane::message() { return *declaration().mutable_plane(); }
v1::SingleParticle& SingleParticle::message() { return *declaration().mutable_single_particle(); }
v1::ParticleSystem& ParticleSystem::message() { return *declaration().mutable_particle_system(); }

void SimulationBox::inputsSent() { pending_.reset(); }

}  // namespace demlink::client
