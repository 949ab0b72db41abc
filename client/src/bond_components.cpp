/// Typed setters of parallel bonds (see the header).
#include "demlink/client/bond_components.hpp"

#include <utility>

#include "demlink/v1/protocol.pb.h"

namespace demlink::client {

ParallelBonds::ParallelBonds(std::string name) : Component(std::move(name)) {
  declaration().mutable_parallel_bonds();
}
ParallelBonds& ParallelBonds::setStiffnessPerArea(double normal, double shear) {
  message().set_normal_stiffness_per_area(normal);
  message().set_shear_stiffness_per_area(shear);
  return *this;
}
ParallelBonds& ParallelBonds::setStrength(double tensile, double shear) {
  message().set_tensile_strength(tensile);
  message().set_shear_strength(shear);
  return *this;
}
ParallelBonds& ParallelBonds::setGapTolerance(double metres) {
  message().set_gap_tolerance(metres);
  return *this;
}
ParallelBonds& ParallelBonds::setRadiusMultiplier(double lambda) {
  message().set_radius_multiplier(lambda);
  return *this;
}
ParallelBonds& ParallelBonds::setCreateTime(double seconds) {
  message().set_create_time(seconds);
  return *this;
}
ParallelBonds& ParallelBonds::setFraction(double fraction, std::uint64_t seed) {
  message().set_fraction(fraction);
  message().set_seed(seed);
  return *this;
}
ParallelBonds& ParallelBonds::addMaterial(const std::string& material) {
  message().add_materials(material);
  return *this;
}
ParallelBonds& ParallelBonds::setBox(const Vec3& centre, const Vec3& size, const Quat& orientation) {
  auto* box = message().mutable_region()->mutable_box();
  *box->mutable_centre() = toProto(centre);
  *box->mutable_size() = toProto(size);
  *box->mutable_orientation() = toProto(orientation);
  return *this;
}
ParallelBonds& ParallelBonds::setSphere(const Vec3& centre, double radius) {
  auto* sphere = message().mutable_region()->mutable_sphere();
  *sphere->mutable_centre() = toProto(centre);
  sphere->set_radius(radius);
  return *this;
}
ParallelBonds& ParallelBonds::attachTo(const std::string& meshComponent) {
  message().mutable_region()->set_attached_to(meshComponent);
  return *this;
}
v1::ParallelBonds& ParallelBonds::message() { return *declaration().mutable_parallel_bonds(); }

}  // namespace demlink::client
