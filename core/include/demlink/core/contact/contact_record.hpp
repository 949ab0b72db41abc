#pragma once
/// What the force stage records for contact output when a scene asks for it
/// (stage pass `contact_recording`): one ContactRecord per contact on the
/// output's steps, and per mesh triangle the loads of every step with their
/// time integrals (load and wear maps). A scene without contact output runs a
/// force-stage instantiation without any of this (contact_stage.hpp).
///
/// Conventions: body a is always a particle; body b is a particle, a plane, a
/// mesh triangle or a deformable-surface triangle. `normal` points from b to a,
/// forces are those ON a, so the normal component F_n = normal_force . normal is
/// positive when the contact pushes a away from b (negative only when cohesion
/// outweighs the elastic and damping force).
#include <cstdint>
#include <vector>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

enum class ContactKind : std::uint8_t {
  kParticle = 0,    ///< b is another particle; other = its id
  kPlane = 1,       ///< b is a plane; other = the plane's index
  kMesh = 2,        ///< b is a mesh triangle; other = the mesh's index
  kDeformable = 3,  ///< b is a deformable surface's triangle; other = the body's index
};

/// One contact at a recorded force evaluation.
struct ContactRecord {
  ContactKind kind = ContactKind::kParticle;
  std::uint64_t particle = 0;  ///< id of particle a
  std::uint64_t other = 0;     ///< id of particle b, or the index of the plane, mesh or deformable body
  std::uint32_t triangle = 0;  ///< the triangle of a mesh or deformable surface; 0 otherwise
  Vec3 centre{Vec3::Zero()};   ///< centre of a [m]
  Vec3 other_point{Vec3::Zero()};  ///< centre of b (particle) or the contact point on the wall [m]
  Vec3 contact_point{Vec3::Zero()};  ///< middle of the overlap (pairs) or the point on the wall [m]
  Vec3 normal{Vec3::Zero()};         ///< unit normal from b towards a [-]
  double overlap = 0.0;              ///< [m]
  Vec3 normal_force{Vec3::Zero()};   ///< normal part of the force on a [N]
  Vec3 tangential_force{Vec3::Zero()};  ///< tangential part of the force on a [N]
};

/// The contacts of one force evaluation.
struct ContactSnapshot {
  std::uint64_t step = 0;        ///< world step count the forces belong to
  bool valid = false;            ///< a snapshot was taken
  std::vector<ContactRecord> contacts;
};

/// Loads of the particles on one mesh triangle. The current values are those of
/// the last force evaluation; the integrals run over every step since the
/// output was requested (or the run was restored).
struct TriangleLoad {
  Vec3 force{Vec3::Zero()};         ///< sum of the contact forces on the triangle [N]
  double normal_force = 0.0;        ///< sum of the contacts' normal components F_n, pressing positive [N]
  double tangential_force = 0.0;    ///< sum of the contacts' |F_t| [N]
  double normal_impulse = 0.0;      ///< time integral of normal_force [N s]
  double tangential_impulse = 0.0;  ///< time integral of tangential_force [N s]
  /// Archard work: time integral of F_n |v_t| summed over the contacts [N m], v_t the
  /// particle's slip velocity relative to the triangle at the contact point. Archard's
  /// law makes the worn volume V = K / H * (this), K the wear coefficient and H the
  /// hardness of the wall.
  double archard_work = 0.0;
  double friction_work = 0.0;       ///< time integral of |F_t| |v_t| [J]: frictional (and tangential damping) work
};

/// What a scene asks of the contact output (World::setContactOutput).
struct ContactOutputSettings {
  /// Record every contact at steps that are multiples of this (and at initialisation); 0: never.
  std::uint64_t every_steps = 0;
  bool mesh_loads = false;  ///< accumulate TriangleLoad per mesh triangle every step

  [[nodiscard]] bool active() const { return every_steps > 0 || mesh_loads; }
};

/// Where a contact pass puts what it records; null pointers record nothing.
struct ContactRecording {
  std::vector<ContactRecord>* contacts = nullptr;  ///< this evaluation's contact records
  std::vector<TriangleLoad>* loads = nullptr;      ///< per triangle of the surface
  double dt = 0.0;        ///< weight of this evaluation in the integrals [s] (0 at initialisation)
  ContactKind kind = ContactKind::kPlane;
  std::uint64_t index = 0;  ///< plane, mesh or deformable body index
};

}  // namespace demlink::core
