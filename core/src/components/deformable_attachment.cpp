/// Deformable body carried by a mesh (contract in deformable_attachment.hpp).
#include "demlink/core/components/deformable_attachment.hpp"

#include "demlink/core/deformable/deformable_body.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/walls/coupled_motion.hpp"
#include "demlink/core/components/component_world.hpp"

namespace demlink::core {

DeformableAttachment::DeformableAttachment(std::string name, std::size_t bodyIndex, std::size_t meshIndex)
    : WorldComponent(std::move(name)), body_(bodyIndex), mesh_(meshIndex) {}

void DeformableAttachment::initialize(ComponentWorld& world) {
  if (mesh_ >= world.meshes().size()) {
    throw InputError(name() + ".attached_to", std::to_string(mesh_), "no mesh body of that index");
  }
  if (body_ >= world.deformableBodies().size()) {
    throw InputError(name() + ".attached_to", std::to_string(body_), "no deformable body of that index");
  }
  initial_orientation_ = world.meshes()[mesh_].orientation();
}

void DeformableAttachment::insertAndRemove(ComponentWorld& world) {
  const MeshBody& mesh = world.meshes()[mesh_];
  const RigidTwist twist{mesh.linearVelocity(), mesh.angularVelocity()};
  // The mesh is at t + dt already; the body takes the pose at t and moves it by the twist.
  const RigidPose start = advancePose({mesh.position(), mesh.orientation() * initial_orientation_.conjugate()}, twist,
                                      -world.settings().time_step);
  world.deformableBody(body_).setDrivenPose(start.position, start.orientation, twist.linear, twist.angular);
}

}  // namespace demlink::core
