/// Typed setters and getters of sources, sinks and pit generators (see the header).
#include "demlink/client/particle_components.hpp"

#include <utility>

#include "demlink/v1/protocol.pb.h"

namespace demlink::client {
namespace {

CountAndMass fromProto(const v1::CountAndMass& value) { return {value.count(), value.mass()}; }

void setBoxVolume(v1::Volume& volume, const Vec3& centre, const Vec3& size, const Quat& orientation) {
  auto* box = volume.mutable_box();
  *box->mutable_centre() = toProto(centre);
  *box->mutable_size() = toProto(size);
  *box->mutable_orientation() = toProto(orientation);
}

}  // namespace

ClumpTemplate::ClumpTemplate(std::string name) : Component(std::move(name)) {
  declaration().mutable_clump_template();
}
ClumpTemplate& ClumpTemplate::addSphere(const Vec3& offset, double radius) {
  v1::ClumpSphere* sphere = message().add_spheres();
  *sphere->mutable_offset() = toProto(offset);
  sphere->set_radius(radius);
  return *this;
}
v1::ClumpTemplate& ClumpTemplate::message() { return *declaration().mutable_clump_template(); }

ParticleSource::ParticleSource(std::string name) : Component(std::move(name)) {
  declaration().mutable_particle_source();
}
ParticleSource& ParticleSource::setMaterial(const std::string& material) {
  message().set_material(material);
  return *this;
}
ParticleSource& ParticleSource::setRadius(double metres) {
  message().mutable_sizes()->set_radius(metres);
  return *this;
}
ParticleSource& ParticleSource::setRadiusRange(double rMin, double rMax) {
  auto* range = message().mutable_sizes()->mutable_uniform();
  range->set_r_min(rMin);
  range->set_r_max(rMax);
  return *this;
}
ParticleSource& ParticleSource::setLinearSizes(double rMin, double rMax, double weightAtMin, double weightAtMax) {
  auto* linear = message().mutable_sizes()->mutable_linear();
  linear->set_r_min(rMin);
  linear->set_r_max(rMax);
  linear->set_weight_at_min(weightAtMin);
  linear->set_weight_at_max(weightAtMax);
  return *this;
}
ParticleSource& ParticleSource::setNormalSizes(double mean, double std, double rMin, double rMax) {
  auto* normal = message().mutable_sizes()->mutable_normal();
  normal->set_mean(mean);
  normal->set_std(std);
  normal->set_r_min(rMin);
  normal->set_r_max(rMax);
  return *this;
}
ParticleSource& ParticleSource::setDiscreteSizes(const std::vector<double>& radii, const std::vector<double>& weights) {
  auto* discrete = message().mutable_sizes()->mutable_discrete();
  discrete->mutable_radii()->Assign(radii.begin(), radii.end());
  discrete->mutable_weights()->Assign(weights.begin(), weights.end());
  return *this;
}
ParticleSource& ParticleSource::setBox(const Vec3& centre, const Vec3& halfExtents, const Quat& orientation) {
  auto* box = message().mutable_box();
  *box->mutable_centre() = toProto(centre);
  *box->mutable_half_extents() = toProto(halfExtents);
  *box->mutable_orientation() = toProto(orientation);
  return *this;
}
ParticleSource& ParticleSource::setDisc(const Vec3& centre, const Vec3& normal, double radius, double thickness) {
  auto* disc = message().mutable_disc();
  *disc->mutable_centre() = toProto(centre);
  *disc->mutable_normal() = toProto(normal);
  disc->set_radius(radius);
  disc->set_thickness(thickness);
  return *this;
}
ParticleSource& ParticleSource::setRateParticles(double perSecond) {
  message().clear_rate_kg_per_s();
  message().set_rate_particles_per_s(perSecond);
  return *this;
}
ParticleSource& ParticleSource::setRateMass(double kgPerSecond) {
  message().clear_rate_particles_per_s();
  message().set_rate_kg_per_s(kgPerSecond);
  return *this;
}
ParticleSource& ParticleSource::setStartTime(double seconds) {
  message().set_start_time(seconds);
  return *this;
}
ParticleSource& ParticleSource::setStopTime(double seconds) {
  message().set_stop_time(seconds);
  return *this;
}
ParticleSource& ParticleSource::setVelocity(const Vec3& velocity) {
  *message().mutable_velocity() = toProto(velocity);
  return *this;
}
ParticleSource& ParticleSource::setSeed(std::uint64_t seed) {
  message().set_seed(seed);
  return *this;
}
ParticleSource& ParticleSource::attachTo(const std::string& meshComponent) {
  message().set_attached_mesh(meshComponent);
  return *this;
}
ParticleSource& ParticleSource::setClumpTemplate(const std::string& templateName) {
  message().set_clump_template(templateName);
  return *this;
}
CountAndMass ParticleSource::insertedInterval() const { return fromProto(outputs().particle_source().interval()); }
CountAndMass ParticleSource::insertedTotal() const { return fromProto(outputs().particle_source().total()); }
CountAndMass ParticleSource::shortfallTotal() const {
  return fromProto(outputs().particle_source().shortfall_total());
}

ParticleSink::ParticleSink(std::string name) : Component(std::move(name)) { declaration().mutable_particle_sink(); }
ParticleSink& ParticleSink::setBox(const Vec3& centre, const Vec3& size, const Quat& orientation) {
  setBoxVolume(*message().mutable_region(), centre, size, orientation);
  return *this;
}
ParticleSink& ParticleSink::setSphere(const Vec3& centre, double radius) {
  auto* sphere = message().mutable_region()->mutable_sphere();
  *sphere->mutable_centre() = toProto(centre);
  sphere->set_radius(radius);
  return *this;
}
ParticleSink& ParticleSink::attachTo(const std::string& meshComponent) {
  message().mutable_region()->set_attached_to(meshComponent);
  return *this;
}
ParticleSink& ParticleSink::setVelocity(const Vec3& velocity) {
  *message().mutable_region()->mutable_velocity() = toProto(velocity);
  return *this;
}
ParticleSink& ParticleSink::setSampleInterval(double seconds) {
  message().set_sample_interval(seconds);
  return *this;
}
void ParticleSource::setEnabled(bool on) {
  if (!pending_) pending_.reset(new v1::ParticleSourceInput());
  pending_->set_enabled(on);
}
void ParticleSource::changeRate(double rate) {
  if (!pending_) pending_.reset(new v1::ParticleSourceInput());
  if (message().has_rate_kg_per_s()) {
    pending_->set_rate_kg_per_s(rate);
  } else {
    pending_->set_rate_particles_per_s(rate);
  }
}
void ParticleSource::writeInputs(v1::DataPackage& package) const {
  if (pending_) *package.mutable_particle_source_input() = *pending_;
}

void ParticleSink::setEnabled(bool on) {
  if (!pending_) pending_.reset(new v1::ParticleSinkInput());
  pending_->set_enabled(on);
}
void ParticleSink::moveTo(const Vec3& centre) {
  if (!pending_) pending_.reset(new v1::ParticleSinkInput());
  *pending_->mutable_region()->mutable_centre() = toProto(centre);
}
void ParticleSink::writeInputs(v1::DataPackage& package) const {
  if (pending_) *package.mutable_particle_sink_input() = *pending_;
}

void ParticleSink::prepareDeclaration() {
  if (message().sample_interval() == 0.0 && message().sample_every_steps() == 0) {
    message().set_sample_interval(communicationInterval());
  }
}
CountAndMass ParticleSink::removedInterval() const { return fromProto(outputs().particle_sink().interval()); }
CountAndMass ParticleSink::removedTotal() const { return fromProto(outputs().particle_sink().total()); }

PitGenerator::PitGenerator(std::string name) : Component(std::move(name)) { declaration().mutable_pit_generator(); }
PitGenerator& PitGenerator::setMaterial(const std::string& material) {
  message().set_material(material);
  return *this;
}
PitGenerator& PitGenerator::setRadius(double metres) {
  message().mutable_sizes()->set_radius(metres);
  return *this;
}
PitGenerator& PitGenerator::setRadiusRange(double rMin, double rMax) {
  auto* range = message().mutable_sizes()->mutable_uniform();
  range->set_r_min(rMin);
  range->set_r_max(rMax);
  return *this;
}
PitGenerator& PitGenerator::setBox(const Vec3& lower, const Vec3& upper) {
  *message().mutable_lower() = toProto(lower);
  *message().mutable_upper() = toProto(upper);
  return *this;
}
PitGenerator& PitGenerator::setTargetHeight(double metres) {
  message().set_target_height(metres);
  return *this;
}
PitGenerator& PitGenerator::setSeed(std::uint64_t seed) {
  message().set_seed(seed);
  return *this;
}

PitGenerator& PitGenerator::setClumpTemplate(const std::string& templateName) {
  message().set_clump_template(templateName);
  return *this;
}

PitGenerator& PitGenerator::setClods(double fraction, double radius, const std::string& bondsComponent) {
  message().set_clod_fraction(fraction);
  message().set_clod_radius(radius);
  message().set_clod_bonds(bondsComponent);
  return *this;
}

v1::ParticleSource& ParticleSource::message() { return *declaration().mutable_particle_source(); }
v1::ParticleSink& ParticleSink::message() { return *declaration().mutable_particle_sink(); }
v1::PitGenerator& PitGenerator::message() { return *declaration().mutable_pit_generator(); }

void ParticleSource::inputsSent() { pending_.reset(); }
void ParticleSink::inputsSent() { pending_.reset(); }

}  // namespace demlink::client
