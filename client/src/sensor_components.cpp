/// Typed setters and getters of region sensors, flow sensors and particle views.
#include "demlink/client/sensor_components.hpp"

#include <limits>
#include <utility>

#include "demlink/v1/protocol.pb.h"

namespace demlink::client {
namespace {

CountAndMass fromProto(const v1::CountAndMass& value) { return {value.count(), value.mass()}; }

}  // namespace

RegionSensor::RegionSensor(std::string name) : Component(std::move(name)) {
  declaration().mutable_region_sensor();
}
RegionSensor& RegionSensor::setBox(const Vec3& centre, const Vec3& size, const Quat& orientation) {
  auto* box = message().mutable_region()->mutable_box();
  *box->mutable_centre() = toProto(centre);
  *box->mutable_size() = toProto(size);
  *box->mutable_orientation() = toProto(orientation);
  return *this;
}
RegionSensor& RegionSensor::setSphere(const Vec3& centre, double radius) {
  auto* sphere = message().mutable_region()->mutable_sphere();
  *sphere->mutable_centre() = toProto(centre);
  sphere->set_radius(radius);
  return *this;
}
RegionSensor& RegionSensor::attachTo(const std::string& bodyComponent) {
  message().mutable_region()->set_attached_to(bodyComponent);
  return *this;
}
RegionSensor& RegionSensor::setVelocity(const Vec3& velocity) {
  *message().mutable_region()->mutable_velocity() = toProto(velocity);
  return *this;
}
RegionSensor& RegionSensor::setSampleInterval(double seconds) {
  message().set_sample_interval(seconds);
  return *this;
}
void RegionSensor::prepareDeclaration() {
  if (message().sample_interval() == 0.0 && message().sample_every_steps() == 0) {
    message().set_sample_interval(communicationInterval());
  }
}
v1::RegionInput& RegionSensor::pending() {
  if (!pending_) pending_.reset(new v1::RegionInput());
  return *pending_;
}
void RegionSensor::moveTo(const Vec3& centre) { *pending().mutable_centre() = toProto(centre); }
void RegionSensor::turnTo(const Quat& orientation) { *pending().mutable_orientation() = toProto(orientation); }
void RegionSensor::resizeBox(const Vec3& size) { *pending().mutable_size() = toProto(size); }
void RegionSensor::resizeSphere(double radius) { pending().set_radius(radius); }
void RegionSensor::writeInputs(v1::DataPackage& package) const {
  if (pending_) *package.mutable_region_sensor_input() = *pending_;
}

std::uint64_t RegionSensor::count() const { return outputs().region_sensor().count(); }
double RegionSensor::mass() const { return outputs().region_sensor().mass(); }
std::uint64_t RegionSensor::bondsIntact() const { return outputs().region_sensor().bonds_intact(); }
std::uint64_t RegionSensor::bondsBroken() const { return outputs().region_sensor().bonds_broken(); }
// An empty region is sent no centre of mass or mean velocity: zeros here (the unset
// fields' values), never NaN; count() tells an empty region apart.
Vec3 RegionSensor::centreOfMass() const { return fromProto(outputs().region_sensor().centre_of_mass()); }
Vec3 RegionSensor::meanVelocity() const { return fromProto(outputs().region_sensor().mean_velocity()); }

FlowSensor::FlowSensor(std::string name) : Component(std::move(name)) { declaration().mutable_flow_sensor(); }
FlowSensor& FlowSensor::setRectangle(const Vec3& centre, const Vec3& normal, double length, double width,
                                     const Vec3& lengthAxis) {
  auto* rectangle = message().mutable_surface()->mutable_rectangle();
  *rectangle->mutable_centre() = toProto(centre);
  *rectangle->mutable_normal() = toProto(normal);
  rectangle->set_length(length);
  rectangle->set_width(width);
  // A zero axis means "any perpendicular direction": leave the field omitted.
  if (lengthAxis.x != 0.0 || lengthAxis.y != 0.0 || lengthAxis.z != 0.0) {
    *rectangle->mutable_length_axis() = toProto(lengthAxis);
  }
  return *this;
}
FlowSensor& FlowSensor::setDisc(const Vec3& centre, const Vec3& normal, double radius) {
  auto* disc = message().mutable_surface()->mutable_disc();
  *disc->mutable_centre() = toProto(centre);
  *disc->mutable_normal() = toProto(normal);
  disc->set_radius(radius);
  return *this;
}
FlowSensor& FlowSensor::attachTo(const std::string& bodyComponent) {
  message().mutable_surface()->set_attached_to(bodyComponent);
  return *this;
}
FlowSensor& FlowSensor::setVelocity(const Vec3& velocity) {
  *message().mutable_surface()->mutable_velocity() = toProto(velocity);
  return *this;
}
FlowSensor& FlowSensor::setSampleInterval(double seconds) {
  message().set_sample_interval(seconds);
  return *this;
}
void FlowSensor::prepareDeclaration() {
  if (message().sample_interval() == 0.0 && message().sample_every_steps() == 0) {
    message().set_sample_interval(communicationInterval());
  }
}
CountAndMass FlowSensor::positiveInterval() const { return fromProto(outputs().flow_sensor().positive_interval()); }
CountAndMass FlowSensor::negativeInterval() const { return fromProto(outputs().flow_sensor().negative_interval()); }
CountAndMass FlowSensor::positiveTotal() const { return fromProto(outputs().flow_sensor().positive_total()); }
CountAndMass FlowSensor::negativeTotal() const { return fromProto(outputs().flow_sensor().negative_total()); }

ParticleView::ParticleView(std::string name) : Component(std::move(name)) { declaration().mutable_particle_view(); }
ParticleView& ParticleView::setMaxCount(std::uint32_t count) {
  message().set_max_count(count);
  return *this;
}
std::uint64_t ParticleView::totalCount() const { return view().total_count(); }
std::uint32_t ParticleView::stride() const { return view().stride(); }
namespace {
std::vector<Vec3> triples(const google::protobuf::RepeatedField<float>& p) {
  std::vector<Vec3> out;
  out.reserve(static_cast<std::size_t>(p.size()) / 3);
  for (int i = 0; i + 2 < p.size(); i += 3) out.push_back({p[i], p[i + 1], p[i + 2]});
  return out;
}
}  // namespace
std::vector<Vec3> ParticleView::positions() const { return triples(view().positions()); }
std::vector<Vec3> ParticleView::velocities() const { return triples(view().velocities()); }
std::vector<std::uint64_t> ParticleView::ids() const { return {view().ids().begin(), view().ids().end()}; }

v1::RegionSensor& RegionSensor::message() { return *declaration().mutable_region_sensor(); }
v1::FlowSensor& FlowSensor::message() { return *declaration().mutable_flow_sensor(); }
v1::ParticleView& ParticleView::message() { return *declaration().mutable_particle_view(); }

void RegionSensor::inputsSent() { pending_.reset(); }
const v1::ParticleViewOutput& ParticleView::view() const { return outputs().particle_view(); }

}  // namespace demlink::client
