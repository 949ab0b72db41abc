#pragma once
/// Carries the driven nodes of a deformable body with a rigid mesh body (a scene's
/// mass_spring_body / fem_body "attached_to" a rigid_body, facet_body or mesh_body):
/// every step, after the meshes moved to t + dt (stage insert_remove) and before the
/// deformable bodies move their nodes (stage deformable_motion), the body's driving pose
/// becomes the mesh's pose at t relative to its pose at initialisation, with its twist:
///   position = mesh reference point,  orientation = q_mesh q_mesh(0)^-1  (both at t),
///   twist    = the mesh's linear and angular velocity;
/// the body carries that pose by the twist to t + dt, where the mesh is (exact for the
/// constant twist a mesh keeps over a step).
/// The body's driven reference must be the mesh's reference point at t = 0 (the scene
/// translator sets it), so the driven nodes keep their place on the mesh.
#include <cstddef>
#include <string>

#include "demlink/core/components/world_component.hpp"
#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

class DeformableAttachment final : public WorldComponent {
 public:
  /// `bodyIndex` into World::deformableBodies(), `meshIndex` into World::meshes(); both
  /// are checked by initialize() (InputError naming "<name>.attached_to").
  DeformableAttachment(std::string name, std::size_t bodyIndex, std::size_t meshIndex);

  [[nodiscard]] std::string_view kind() const override { return "deformable_attachment"; }
  [[nodiscard]] StageSet stages() const override { return stageBit(Stage::kInsertRemove); }
  void initialize(ComponentWorld& world) override;
  void insertAndRemove(ComponentWorld& world) override;

  [[nodiscard]] std::size_t bodyIndex() const { return body_; }
  [[nodiscard]] std::size_t meshIndex() const { return mesh_; }

 private:
  std::size_t body_;
  std::size_t mesh_;
  Quat initial_orientation_ = Quat::Identity();
};

}  // namespace demlink::core
