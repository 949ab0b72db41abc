#pragma once
/// Mass-spring body: nodes with mass joined by spring-dampers (Provot, "Deformation
/// constraints in a mass-spring model to describe rigid cloth behavior", 1995), the
/// solver paper's "MS" bodies, with springs that tear.
///
/// Spring (i, j): f_i = [k (|x_j - x_i| - L0) + c (v_j - v_i).e] e,  e = (x_j - x_i)/|x_j - x_i|,
/// f_j = -f_i. Integrated with velocity Verlet like the particles (half kick, drift in
/// beginStep; spring and contact forces, tearing, half kick in endStep). A spring breaks
/// for good when |elastic + damping force| > break_force or strain |L - L0|/L0 > break_strain.
/// Stable step of the explicit scheme: dt < 2/omega_max (sqrt(1 + zeta^2) - zeta) with
/// omega_max^2 <= max over free nodes of sum_springs 2 k / m_node and zeta = (max over free
/// nodes of sum_springs c / m_node + node_damping / 2) / omega_max (Gershgorin bounds on
/// M^-1 K and M^-1 C; the damped central-difference limit).
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "demlink/core/deformable/deformable_body.hpp"
#include "demlink/core/deformable/node_constraints.hpp"
#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

struct SpringSpec {
  std::uint32_t a = 0;
  std::uint32_t b = 0;
  double stiffness = 0.0;     ///< [N/m]
  double damping = 0.0;       ///< [N s/m]
  double rest_length = -1.0;  ///< [m]; < 0: the initial distance
};

/// Where a mass-spring body's nodes and springs come from (exactly one of the three); the
/// constraints (node_constraints.hpp) take node indices, and a node cannot be both fixed and driven.
struct MassSpringSpec : NodeConstraintSpec {
  std::string name;
  std::uint32_t material = 0;
  double total_mass = 0.0;  ///< [kg], spread equally over the nodes
  double stiffness = 0.0;   ///< [N/m] of structural springs built by (a) and (b)
  double damping = 0.0;     ///< [N s/m] of structural springs built by (a) and (b)
  /// Extra springs for (a): shear springs across cell diagonals and bending springs
  /// over two cells, each with stiffness * factor (0: none).
  double shear_factor = 0.0;
  double bending_factor = 0.0;
  /// Drag of a surrounding medium on every free node, f = -node_damping m v [1/s]. Spring
  /// dampers act only along the springs, so the out-of-plane motion of a flat sheet is
  /// damped only to second order in its slope; this damps it (0: none).
  double node_damping = 0.0;

  /// (a) a box [lo, hi] subdivided into a node lattice at `node_spacing` [m] (a sheet
  /// when one extent is below the spacing: a single layer).
  struct Box {
    Vec3 lo = Vec3::Zero();
    Vec3 hi = Vec3::Zero();
    double node_spacing = 0.0;
    /// The nodes the lattice gets (before it is built, for a memory check); +inf when an
    /// axis is not positive or finite [-].
    [[nodiscard]] double nodeCount() const;
  };
  std::optional<Box> box;
  /// (b) an STL surface: nodes = distinct vertices, springs = distinct edges.
  std::string stl_path;
  /// (c) explicit nodes, springs and surface triangles.
  std::vector<Vec3> nodes;
  std::vector<SpringSpec> springs;
  std::vector<std::array<std::uint32_t, 3>> triangles;

  /// Tearing thresholds (infinity: never).
  double break_force = std::numeric_limits<double>::infinity();   ///< [N]
  double break_strain = std::numeric_limits<double>::infinity();  ///< [-]
};

/// One broken spring, for the CSV and the VTK output.
struct BrokenSpring {
  std::uint32_t spring = 0;
  double time = 0.0;  ///< [s]
  Vec3 position = Vec3::Zero();  ///< midpoint when it broke [m]
  double force = 0.0;            ///< |force| when it broke [N]
  double strain = 0.0;
};

class MassSpringBody final : public DeformableBody {
 public:
  /// Builds and validates (InputError naming "<fieldPrefix>.<field>" and the value).
  MassSpringBody(const MassSpringSpec& spec, const std::string& fieldPrefix);

  // DeformableBody interface: see deformable_body.hpp.
  [[nodiscard]] const std::string& name() const override { return name_; }
  [[nodiscard]] std::string_view kind() const override { return "mass_spring"; }
  void beginStep(double dt, const Vec3& gravity) override;
  void endStep(double dt, const Vec3& gravity) override;
  [[nodiscard]] DeformableSurface& surface() override { return surface_; }
  [[nodiscard]] const DeformableSurface& surface() const override { return surface_; }
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
  [[nodiscard]] std::uint64_t brokenCount() const override;
  [[nodiscard]] double kineticEnergy() const override;
  [[nodiscard]] double totalMass() const override;
  void save(StateWriter& out) const override;
  void restore(StateReader& in) override;

  /// Springs as built (endpoints, stiffness, damping, rest length) and whether each is intact.
  [[nodiscard]] const std::vector<SpringSpec>& springs() const { return springs_; }
  [[nodiscard]] const std::vector<char>& intact() const { return intact_; }
  /// Springs that broke so far, in the order they broke.
  [[nodiscard]] const std::vector<BrokenSpring>& brokenSprings() const { return broken_; }
  /// Elastic + spring potential energy [J] (for the energy tests).
  [[nodiscard]] double springEnergy() const;

 private:
  /// Adds the forces of the intact springs to node_force_; with `tear`, springs over a
  /// threshold break instead (recorded at `time` [s], their triangles deactivated).
  void addSpringForces(bool tear, double time);
  /// The tearing rule: the triangles along a broken spring lose their support.
  void deactivateTrianglesOf(std::uint32_t spring);
  /// The explicit scheme's stable step and what sets it (see the file comment).
  struct StableStep {
    double step = std::numeric_limits<double>::infinity();  ///< [s]
    std::size_t node = 0;        ///< free node with the largest sum of spring stiffness
    double stiffness_sum = 0.0;  ///< that sum [N/m] (0: no free node has a spring)
    double damping_ratio = 0.0;  ///< zeta = (sum c / m) / omega_max, bound over the free nodes
  };
  [[nodiscard]] StableStep stableStep() const;

  std::string name_;
  DeformableSurface surface_;
  std::vector<SpringSpec> springs_;
  std::vector<char> intact_;
  std::vector<BrokenSpring> broken_;
  // Node positions and velocities live in surface_ (every node is a surface node).
  std::vector<Vec3> reference_;       ///< positions as built [m]
  std::vector<Vec3> node_force_;      ///< spring + contact force of the last endStep [N]
  double node_mass_ = 0.0;            ///< [kg], equal for every node
  NodeConstraints constraints_;       ///< fixed and driven nodes, driving pose, reactions
  /// Triangles each spring supports (CSR: spring s -> triangles [offsets[s], offsets[s+1])).
  std::vector<std::uint32_t> spring_triangle_offsets_;
  std::vector<std::uint32_t> spring_triangles_;
  double node_damping_ = 0.0;  ///< [1/s]
  double break_force_ = std::numeric_limits<double>::infinity();
  double break_strain_ = std::numeric_limits<double>::infinity();
  std::uint64_t steps_ = 0;  ///< endStep calls so far (time of a tear = steps_ * dt)
};

}  // namespace demlink::core
