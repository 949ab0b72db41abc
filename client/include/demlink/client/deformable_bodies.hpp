#pragma once
/// Deformable bodies a client declares (docs/deformable.md, "Scene files and clients"): a
/// MassSpringBody (nodes joined by springs that tear) and an FemBody (linear finite
/// elements). Both take the pose of their driven nodes as input each interval and return
/// node displacements, the reactions at the driven and fixed nodes and the broken-spring
/// count.
///
/// Why the driven pose persists like a RigidBody's: a package without a pose would leave
/// the nodes at the last one anyway, and a model that drives the nodes continuously sets
/// it every interval. Before the first setDrivenPose() no pose is sent and the driven nodes
/// stay where they were built.
#include <cstdint>
#include <string>
#include <vector>

#include "demlink/client/component.hpp"

namespace demlink::client {

/// Common inputs and outputs of both kinds.
class DeformableBody : public Component {
 public:
  /// World position of the driving reference point [m] and rotation from the initial
  /// configuration [-]; sent with every later package.
  void setDrivenPose(const Vec3& position, const Quat& orientation = {});
  /// Velocity of the reference point [m/s] and angular velocity, world frame [rad/s].
  void setDrivenVelocity(const Vec3& linear, const Vec3& angular = {});

  /// The reported nodes (DeformableOutputNodes) [-] and their displacements [m].
  [[nodiscard]] std::vector<std::uint32_t> nodes() const;
  [[nodiscard]] std::vector<Vec3> displacements() const;
  /// Displacement of the k-th reported node [m] (std::out_of_range beyond nodes()).
  [[nodiscard]] Vec3 displacement(std::size_t k) const;
  /// Reaction of the driven nodes ON the body [N]; torque about the driving position [N m].
  [[nodiscard]] Vec3 drivenForce() const;
  [[nodiscard]] Vec3 drivenTorque() const;
  /// Reaction of the fixed nodes ON the body [N]; torque about the world origin [N m].
  [[nodiscard]] Vec3 fixedForce() const;
  [[nodiscard]] Vec3 fixedTorque() const;
  [[nodiscard]] std::uint64_t brokenSprings() const;  ///< [-]; 0 for FEM
  [[nodiscard]] double kineticEnergy() const;         ///< [J]
  [[nodiscard]] std::uint64_t nodeCount() const;      ///< nodes of the body [-]

 protected:
  using Component::Component;
  void writeInputs(v1::DataPackage& package) const override;
  // The shared declaration fields, written into whichever of the two bodies was declared
  // (the generated messages stay out of this header).
  void declareMaterial(const std::string& material);
  /// Adds the box [lo, hi] to the driven (true) or fixed node set [m].
  void declareRegion(bool driven, const Vec3& lo, const Vec3& hi);
  void declareDrivenReference(const Vec3& point);
  void declareAttachedTo(const std::string& rigidBody);
  void declareOutputNodes(const std::vector<std::uint32_t>& nodes);

 private:
  bool pose_set_ = false;
  ProtoPtr<v1::DeformableBodyInput> input_;
};

/// The declaration setters both kinds share; `Derived` (MassSpringBody, FemBody) for chaining.
template <class Derived>
class DeformableBodyOf : public DeformableBody {
 public:
  Derived& setMaterial(const std::string& material) {
    declareMaterial(material);
    return self();
  }
  /// Nodes in [lo, hi] are fixed / driven [m].
  Derived& addFixedRegion(const Vec3& lo, const Vec3& hi) {
    declareRegion(false, lo, hi);
    return self();
  }
  Derived& addDrivenRegion(const Vec3& lo, const Vec3& hi) {
    declareRegion(true, lo, hi);
    return self();
  }
  /// The point the driven pose refers to, at t = 0 [m].
  Derived& setDrivenReference(const Vec3& point) {
    declareDrivenReference(point);
    return self();
  }
  /// The driven nodes follow this rigid body (no pose input then).
  Derived& attachTo(const std::string& rigidBody) {
    declareAttachedTo(rigidBody);
    return self();
  }
  /// Report these nodes' displacements (default: the surface nodes, at most 10000).
  Derived& setOutputNodes(const std::vector<std::uint32_t>& nodes) {
    declareOutputNodes(nodes);
    return self();
  }

 protected:
  using DeformableBody::DeformableBody;

 private:
  Derived& self() { return static_cast<Derived&>(*this); }
};

class MassSpringBody : public DeformableBodyOf<MassSpringBody> {
 public:
  explicit MassSpringBody(std::string name);
  /// A node lattice filling [lo, hi] at `nodeSpacing` [m].
  MassSpringBody& setBox(const Vec3& lo, const Vec3& hi, double nodeSpacing);
  MassSpringBody& setStlFile(const std::string& pathOnServer);
  /// Total mass [kg], spring stiffness [N/m] and damping [N s/m].
  MassSpringBody& setSprings(double totalMass, double stiffness, double damping);
  /// Break above |force| [N] or strain [-].
  MassSpringBody& setBreakLimits(double force, double strain);
  [[nodiscard]] v1::MassSpringBody& message();
};

class FemBody : public DeformableBodyOf<FemBody> {
 public:
  explicit FemBody(std::string name);
  /// A Gmsh .msh on the server with E [Pa], nu [-], rho [kg/m^3].
  FemBody& setMesh(const std::string& mshPathOnServer, double youngsModulus, double poissonRatio, double density);
  /// Rayleigh damping C = alpha K + beta M (alpha [s], beta [1/s]).
  FemBody& setRayleigh(double alpha, double beta);
  [[nodiscard]] v1::FemBody& message();
};

}  // namespace demlink::client
