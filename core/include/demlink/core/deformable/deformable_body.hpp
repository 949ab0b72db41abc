#pragma once
/// A body whose shape changes: mass-spring (mass_spring_body.hpp) or linear FEM
/// (fem_body.hpp). The world steps it in two halves around the particle forces:
///
///   beginStep  (stage deformable_motion, after the particles' drift): move the nodes
///              from t to t + dt with the forces known so far and write the surface;
///   ...        particle contacts with the surface at t + dt leave node forces;
///   endStep    (stage deformable_forces, after the force stage): take those contact
///              forces and finish the step (mass-spring: spring forces, tearing and
///              the second half kick; FEM: remember the load for the next solve).
///
/// Driven nodes follow a rigid pose a client (or the scene) sets; fixed nodes stay
/// where they were built. Reactions at both are outputs.
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "demlink/core/deformable/deformable_surface.hpp"
#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

class StateWriter;
class StateReader;

/// Reaction of the constrained nodes on the body: the force and the torque about
/// the driving pose's position that the constraint applies to keep them in place.
struct NodeReaction {
  Vec3 force = Vec3::Zero();   ///< [N]
  Vec3 torque = Vec3::Zero();  ///< [N m]
};

class DeformableBody {
 public:
  virtual ~DeformableBody() = default;

  [[nodiscard]] virtual const std::string& name() const = 0;
  /// "mass_spring" or "fem" (compile report, outputs).
  [[nodiscard]] virtual std::string_view kind() const = 0;

  /// First half of a step (see above); `gravity` [m/s^2].
  virtual void beginStep(double dt, const Vec3& gravity) = 0;
  /// Second half of a step: the surface's nodeForces() hold this step's contact forces.
  virtual void endStep(double dt, const Vec3& gravity) = 0;

  [[nodiscard]] virtual DeformableSurface& surface() = 0;
  [[nodiscard]] virtual const DeformableSurface& surface() const = 0;

  /// Largest stable time step of the body's own integrator [s] (+infinity when it is
  /// unconditionally stable); joins the world's critical-step check.
  [[nodiscard]] virtual double criticalTimeStep() const = 0;
  /// What sets criticalTimeStep(), for the compile report ("stiffest spring k=..", ...).
  [[nodiscard]] virtual std::string criticalTimeStepReason() const = 0;

  /// Pose of the driven node set (world position of the driving reference point,
  /// orientation, twist) at the start of the coming step; beginStep carries it by the twist
  /// to the step's end and puts the driven nodes there (one rule for every kind of body:
  /// NodeConstraints, node_constraints.hpp). Throws InputError for non-finite values.
  /// Bodies without driven nodes ignore it.
  virtual void setDrivenPose(const Vec3& position, const Quat& orientation, const Vec3& linearVelocity,
                             const Vec3& angularVelocity) = 0;
  [[nodiscard]] virtual bool hasDrivenNodes() const = 0;
  /// Reaction at the driven nodes (torque about the driving position) and at the fixed nodes
  /// (torque about the world origin) as of the last endStep.
  [[nodiscard]] virtual NodeReaction drivenReaction() const = 0;
  [[nodiscard]] virtual NodeReaction fixedReaction() const = 0;

  /// All nodes (surface nodes are the first surface().positions().size() of them).
  [[nodiscard]] virtual std::size_t nodeCount() const = 0;
  [[nodiscard]] virtual Vec3 nodePosition(std::size_t node) const = 0;
  [[nodiscard]] virtual Vec3 nodeDisplacement(std::size_t node) const = 0;
  [[nodiscard]] virtual Vec3 nodeVelocity(std::size_t node) const = 0;
  /// Number of broken springs (0 for FEM).
  [[nodiscard]] virtual std::uint64_t brokenCount() const = 0;
  /// Kinetic energy [J] and total mass [kg] of the body.
  [[nodiscard]] virtual double kineticEnergy() const = 0;
  [[nodiscard]] virtual double totalMass() const = 0;

  /// Checkpoint payload of what evolves (node state, broken springs, load history).
  virtual void save(StateWriter& out) const = 0;
  /// Reads what save() wrote, checked against this body; throws InputError via the reader.
  virtual void restore(StateReader& in) = 0;
};

}  // namespace demlink::core
