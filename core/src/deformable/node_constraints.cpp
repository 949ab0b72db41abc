/// Fixed and driven node sets of a deformable body (node_constraints.hpp).
#include "demlink/core/deformable/node_constraints.hpp"

#include <cmath>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/state/state_stream.hpp"

namespace demlink::core {

namespace {

std::string vecText(const Vec3& v) {
  return "(" + formatValue(v.x()) + ", " + formatValue(v.y()) + ", " + formatValue(v.z()) + ")";
}

}  // namespace

NodeConstraints::NodeConstraints(const NodeConstraintSpec& spec, const std::vector<Vec3>& nodes,
                                 const NodeLookup& lookup, const std::string& unknownIdReason,
                                 ConstraintOverlap overlap, const std::string& fieldPrefix) {
  if (!spec.driven_reference.allFinite()) {
    throw InputError(fieldPrefix + ".driven_reference", vecText(spec.driven_reference), "must be finite");
  }
  std::vector<NodeRole>& role = role_;
  role.assign(nodes.size(), NodeRole::kFree);
  const auto mark = [&](std::uint32_t node, NodeRole target, const std::string& field) {
    if (role[node] == NodeRole::kFree || role[node] == target) {
      role[node] = target;
    } else if (overlap == ConstraintOverlap::kError) {
      throw InputError(field, std::to_string(node), "node is both fixed and driven");
    }  // kFixedWins: fixed nodes are marked first and stay fixed
  };
  const auto markAll = [&](const std::vector<std::uint32_t>& ids, const std::vector<NodeRegion>& regions,
                           NodeRole target, const std::string& what) {
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const std::string field = fieldPrefix + "." + what + ".nodes[" + std::to_string(k) + "]";
      const std::optional<std::uint32_t> node = lookup(ids[k]);
      if (!node || *node >= nodes.size()) throw InputError(field, std::to_string(ids[k]), unknownIdReason);
      mark(*node, target, field);
    }
    for (std::size_t k = 0; k < regions.size(); ++k) {
      const NodeRegion& region = regions[k];
      const std::string field = fieldPrefix + "." + what + ".regions[" + std::to_string(k) + "]";
      if (!region.lo.allFinite() || !region.hi.allFinite()) {
        throw InputError(field, vecText(region.lo) + " .. " + vecText(region.hi), "must be finite");
      }
      if ((region.lo.array() > region.hi.array()).any()) {
        throw InputError(field + ".hi", vecText(region.hi), "must not be below lo " + vecText(region.lo));
      }
      bool any = false;
      for (std::uint32_t n = 0; n < nodes.size(); ++n) {
        if ((nodes[n].array() >= region.lo.array()).all() && (nodes[n].array() <= region.hi.array()).all()) {
          mark(n, target, field);
          any = true;
        }
      }
      if (!any) {
        throw InputError(field, vecText(region.lo) + " .. " + vecText(region.hi), "contains no node of the body");
      }
    }
  };
  markAll(spec.fixed_nodes, spec.fixed_regions, NodeRole::kFixed, "fixed");
  markAll(spec.driven_nodes, spec.driven_regions, NodeRole::kDriven, "driven");
  for (std::uint32_t n = 0; n < nodes.size(); ++n) {
    if (role[n] == NodeRole::kFixed) fixed_.push_back(n);
    if (role[n] == NodeRole::kDriven) {
      driven_.push_back(n);
      driven_offset_.push_back(nodes[n] - spec.driven_reference);
    }
  }
  pose_.position = spec.driven_reference;
}

void NodeConstraints::setPose(const DrivenPose& pose, const std::string& fieldPrefix) {
  if (!pose.position.allFinite()) {
    throw InputError(fieldPrefix + ".pose.position", vecText(pose.position), "must be finite");
  }
  if (!pose.orientation.coeffs().allFinite() || !(pose.orientation.norm() > 0.0)) {
    throw InputError(fieldPrefix + ".pose.orientation", "(non-finite or zero)", "must be a finite non-zero quaternion");
  }
  if (!pose.linear_velocity.allFinite()) {
    throw InputError(fieldPrefix + ".velocity.linear", vecText(pose.linear_velocity), "must be finite");
  }
  if (!pose.angular_velocity.allFinite()) {
    throw InputError(fieldPrefix + ".velocity.angular", vecText(pose.angular_velocity), "must be finite");
  }
  pose_ = pose;
  pose_.orientation.normalize();
}

void NodeConstraints::advance(double dt) {
  pose_.position += pose_.linear_velocity * dt;
  const double angle = pose_.angular_velocity.norm() * dt;
  if (angle > 0.0) {
    pose_.orientation =
        (Quat(Eigen::AngleAxisd(angle, pose_.angular_velocity.normalized())) * pose_.orientation).normalized();
  }
}

void NodeConstraints::save(StateWriter& out) const {
  out.write(pose_.position);
  out.write(pose_.orientation);
  out.write(pose_.linear_velocity);
  out.write(pose_.angular_velocity);
  for (const NodeReaction* r : {&fixed_reaction_, &driven_reaction_}) {
    out.write(r->force);
    out.write(r->torque);
  }
}

void NodeConstraints::restore(StateReader& in) {
  DrivenPose pose;
  pose.position = in.read<Vec3>();
  pose.orientation = in.read<Quat>();
  pose.linear_velocity = in.read<Vec3>();
  pose.angular_velocity = in.read<Vec3>();
  if (!(std::abs(pose.orientation.norm() - 1.0) < 1.0e-9)) in.fail("driven orientation", "not a unit quaternion");
  NodeReaction reactions[2];
  for (NodeReaction& r : reactions) {
    r.force = in.read<Vec3>();
    r.torque = in.read<Vec3>();
  }
  pose_ = pose;
  fixed_reaction_ = reactions[0];
  driven_reaction_ = reactions[1];
}

}  // namespace demlink::core
