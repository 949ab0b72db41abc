#pragma once
/// Which nodes of a deformable body are fixed, which follow a driving rigid pose, and the
/// reactions at both: the part of MassSpringSpec and FemSpec they share (NodeConstraintSpec)
/// and the state both bodies keep for it (NodeConstraints).
///
/// The driving pose is set for the start of the coming step (a client's sample advanced to
/// the step, a mesh's pose at t, docs/deformable.md); each step first carries it by its twist
/// over dt (p += v dt, q = exp(w dt) q) and then puts every driven node at
///   x = p + R(q) (X - driven_reference),   v_node = v + w x (x - p),
/// X its position as built. Both kinds of body move their driven nodes through advance()
/// and forEachDriven(), so a mass-spring and an FEM body driven by one pose agree.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "demlink/core/deformable/deformable_body.hpp"
#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

class StateWriter;
class StateReader;

/// An axis-aligned box [lo, hi] [m]; a node is inside when lo <= x <= hi in every axis.
struct NodeRegion {
  Vec3 lo = Vec3::Zero();
  Vec3 hi = Vec3::Zero();
};

/// Constraints of a deformable body: node ids (what an id means is the body's: a mass-spring
/// node index, a Gmsh node tag, an index into an FE code's node file) or every node inside a
/// box. A region must hold a node.
struct NodeConstraintSpec {
  std::vector<std::uint32_t> fixed_nodes;
  std::vector<NodeRegion> fixed_regions;
  std::vector<std::uint32_t> driven_nodes;
  std::vector<NodeRegion> driven_regions;
  /// Reference point of the driving pose in the initial configuration [m].
  Vec3 driven_reference = Vec3::Zero();
};

enum class NodeRole : std::uint8_t { kFree, kFixed, kDriven };

/// What happens to a node that is both fixed and driven.
enum class ConstraintOverlap : std::uint8_t {
  kError,      ///< InputError on the driven entry that names it
  kFixedWins,  ///< the node is fixed
};

/// The body node an id names, or nothing when there is no such node.
using NodeLookup = std::function<std::optional<std::uint32_t>(std::uint32_t id)>;

/// Pose of the driven node set: world position of the driving reference point [m],
/// orientation relative to the initial configuration, twist [m/s], [rad/s].
struct DrivenPose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
  Vec3 linear_velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
};

class NodeConstraints {
 public:
  NodeConstraints() = default;
  /// Resolves `spec` over the nodes as built (`nodes` [m]). Errors are InputError naming
  /// "<fieldPrefix>.fixed_nodes[i]", ".driven_regions[k]", ".driven_reference", ...; an id
  /// `lookup` does not know gives `unknownIdReason`.
  NodeConstraints(const NodeConstraintSpec& spec, const std::vector<Vec3>& nodes, const NodeLookup& lookup,
                  const std::string& unknownIdReason, ConstraintOverlap overlap, const std::string& fieldPrefix);

  [[nodiscard]] NodeRole role(std::size_t node) const { return role_[node]; }
  [[nodiscard]] const std::vector<std::uint32_t>& fixed() const { return fixed_; }    ///< ascending
  [[nodiscard]] const std::vector<std::uint32_t>& driven() const { return driven_; }  ///< ascending

  /// Sets the pose for the start of the coming step (orientation normalised); InputError
  /// "<fieldPrefix>.pose.position", ... for a non-finite value or a zero quaternion.
  void setPose(const DrivenPose& pose, const std::string& fieldPrefix);
  [[nodiscard]] const DrivenPose& pose() const { return pose_; }
  /// Carries the pose by its twist over `dt` [s]: the pose at the end of the step.
  void advance(double dt);
  /// Calls visit(node, position, velocity) for every driven node at the current pose.
  template <class Visit>
  void forEachDriven(Visit&& visit) const {
    const Mat3 rotation = pose_.orientation.toRotationMatrix();
    for (std::size_t k = 0; k < driven_.size(); ++k) {
      const Vec3 arm = rotation * driven_offset_[k];
      visit(driven_[k], Vec3(pose_.position + arm), Vec3(pose_.linear_velocity + pose_.angular_velocity.cross(arm)));
    }
  }

  /// Reactions of the last step (deformable_body.hpp), computed by the body.
  [[nodiscard]] const NodeReaction& fixedReaction() const { return fixed_reaction_; }
  [[nodiscard]] const NodeReaction& drivenReaction() const { return driven_reaction_; }
  void setReactions(const NodeReaction& fixed, const NodeReaction& driven) {
    fixed_reaction_ = fixed;
    driven_reaction_ = driven;
  }

  /// Checkpoint payload: the pose, then the fixed and the driven reaction.
  void save(StateWriter& out) const;
  /// Reads what save() wrote; a non-unit orientation fails through the reader.
  void restore(StateReader& in);

 private:
  std::vector<NodeRole> role_;
  std::vector<std::uint32_t> fixed_;
  std::vector<std::uint32_t> driven_;
  std::vector<Vec3> driven_offset_;  ///< per driven node: X - driven_reference [m]
  DrivenPose pose_;
  NodeReaction fixed_reaction_;
  NodeReaction driven_reaction_;
};

}  // namespace demlink::core
