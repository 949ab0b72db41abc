#pragma once
/// Linear FEM body: the linear transient small-displacement equation
///   M U'' + C U' + K U = F,   C = alpha K + beta M  (Rayleigh; alpha [s], beta [1/s]),
/// as in the solver paper (its eq. 18), integrated by the three-level scheme (gamma = 1/2,
/// beta_N = 1/3; unconditionally stable, A1 factorised once) or by explicit central
/// differences with a lumped mass (cheap, conditionally stable). The paper's printed
/// A-matrices carry sign errors; fem_body.cpp derives the scheme and docs/deformable.md
/// states the correction.
///
/// Two sources of M and K: our assembly from a tetrahedral mesh (Gmsh .msh, linear or
/// quadratic tetrahedra; E, nu, rho; lumped or consistent mass), or Matrix Market files
/// exported by a commercial FE code with node coordinates and surface triangles.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/SparseCore>

#include "demlink/core/deformable/deformable_body.hpp"
#include "demlink/core/deformable/node_constraints.hpp"
#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

enum class FemIntegrator : std::uint8_t { kThreeLevel, kCentralDifference };
enum class FemMass : std::uint8_t { kLumped, kConsistent };

/// Constraints (node_constraints.hpp): for a .msh, Gmsh node tags; for imported matrices,
/// 0-based indices into the node file; regions apply to positions with the offset. A node
/// both fixed and driven is fixed.
struct FemSpec : NodeConstraintSpec {
  std::string name;
  std::uint32_t material = 0;  ///< contact material of the surface
  FemIntegrator integrator = FemIntegrator::kThreeLevel;
  double rayleigh_alpha = 0.0;  ///< [s], multiplies K
  double rayleigh_beta = 0.0;   ///< [1/s], multiplies M

  /// (a) our assembly: a Gmsh .msh (ASCII) with tetrahedra, placed by `offset` [m].
  std::string msh_path;
  double youngs_modulus = 0.0;  ///< [Pa]
  double poisson_ratio = 0.0;
  double density = 0.0;         ///< [kg/m^3]
  FemMass mass = FemMass::kLumped;
  Vec3 offset = Vec3::Zero();  ///< added to every node position, for (b) as well [m]

  /// (b) imported matrices (Matrix Market, 3 DOF per node in node order x,y,z) with the
  /// node coordinates and surface triangles (plain text files, documented in docs/deformable.md).
  std::string mass_matrix_path;
  std::string stiffness_matrix_path;
  std::string damping_matrix_path;  ///< optional; replaces the Rayleigh C
  std::string nodes_path;
  std::string triangles_path;
};

class FemBody final : public DeformableBody {
 public:
  /// Builds (reads, assembles, factorises) and validates; errors are InputError naming
  /// "<fieldPrefix>.<field>" and the value (file errors name the file and line).
  FemBody(const FemSpec& spec, double timeStep, const std::string& fieldPrefix);
  ~FemBody() override;

  // DeformableBody interface: see deformable_body.hpp.
  [[nodiscard]] const std::string& name() const override;
  [[nodiscard]] std::string_view kind() const override { return "fem"; }
  void beginStep(double dt, const Vec3& gravity) override;
  void endStep(double dt, const Vec3& gravity) override;
  [[nodiscard]] DeformableSurface& surface() override;
  [[nodiscard]] const DeformableSurface& surface() const override;
  [[nodiscard]] double criticalTimeStep() const override;
  [[nodiscard]] std::string criticalTimeStepReason() const override;
  void setDrivenPose(const Vec3& position, const Quat& orientation, const Vec3& linearVelocity,
                     const Vec3& angularVelocity) override;
  [[nodiscard]] bool hasDrivenNodes() const override;
  [[nodiscard]] NodeReaction drivenReaction() const override;
  [[nodiscard]] NodeReaction fixedReaction() const override;
  [[nodiscard]] std::size_t nodeCount() const override;
  [[nodiscard]] Vec3 nodePosition(std::size_t node) const override;
  [[nodiscard]] Vec3 nodeDisplacement(std::size_t node) const override;
  [[nodiscard]] Vec3 nodeVelocity(std::size_t node) const override;
  [[nodiscard]] std::uint64_t brokenCount() const override { return 0; }
  [[nodiscard]] double kineticEnergy() const override;
  [[nodiscard]] double totalMass() const override;
  void save(StateWriter& out) const override;
  void restore(StateReader& in) override;

  /// Volume elements for the .vtu output: corner node indices (4 for linear, 10 for
  /// quadratic tetrahedra, Gmsh/VTK node order), empty for imported matrices.
  [[nodiscard]] const std::vector<std::vector<std::uint32_t>>& elements() const;
  /// Von Mises stress per element at its centroid [Pa] (empty for imported matrices).
  [[nodiscard]] std::vector<double> vonMisesStress() const;

  /// Puts the body at rest in static equilibrium, K U = F, under `gravity` [m/s^2], the
  /// surface's current node forces and the constraints (the driven pose as last set): a start
  /// without the drop from the unloaded shape. Throws InputError when nothing is constrained.
  void solveStatic(const Vec3& gravity);
  /// Strain energy U^T K U / 2 [J].
  [[nodiscard]] double strainEnergy() const;
  /// The matrices the body integrates (3 DOF per node in body node order; M lumped or
  /// consistent as built), e.g. to export them in Matrix Market format.
  [[nodiscard]] const Eigen::SparseMatrix<double>& massMatrix() const;
  [[nodiscard]] const Eigen::SparseMatrix<double>& stiffnessMatrix() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace demlink::core
