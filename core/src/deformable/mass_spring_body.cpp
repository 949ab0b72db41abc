/// Mass-spring body (mass_spring_body.hpp): constraints, velocity Verlet in two
/// halves around the particle contacts, tearing, reactions, checkpoint payload.
///
/// One step (dt, gravity g), node mass m, f = spring + contact force of the last evaluation:
///   beginStep: free nodes   v += (f/m + g) dt/2,  x += v dt;
///              driven nodes follow the driving pose advanced by its twist over dt
///              (x = p + R r0, v = v_p + w x (x - p)); fixed nodes stay.
///   (the particles' contacts with the surface at t + dt leave the contact forces)
///   endStep:   f = contact + springs at (x(t+dt), v(t+dt/2)) - node_damping m v(t+dt/2);
///              springs over a threshold break first and carry no force;
///              free nodes v += (f/m + g) dt/2;
///              reactions of the constrained nodes (below).
/// Reaction of a constrained node n: R_n = m a_n - f_n - m g, the force the constraint
/// must add so the node has its prescribed acceleration a_n (0 for fixed nodes,
/// w x (w x (x_n - p)) for driven ones under a constant twist). fixedReaction() sums
/// R_n over the fixed nodes (torque about the world origin), drivenReaction() over the
/// driven nodes (torque about the driving position p).
#include "demlink/core/deformable/mass_spring_body.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "mass_spring_builders.hpp"

namespace demlink::core {

template <>
struct StateCodec<BrokenSpring> {
  static constexpr std::size_t kBytes = sizeof(std::uint32_t) + 6 * sizeof(double);
  static void write(StateWriter& out, const BrokenSpring& b) {
    out.write(b.spring);
    out.write(b.time);
    out.write(b.position);
    out.write(b.force);
    out.write(b.strain);
  }
  static void read(StateReader& in, BrokenSpring& b) {
    b.spring = in.read<std::uint32_t>();
    b.time = in.read<double>();
    b.position = in.read<Vec3>();
    b.force = in.read<double>();
    b.strain = in.read<double>();
  }
};

MassSpringBody::MassSpringBody(const MassSpringSpec& spec, const std::string& fieldPrefix) : name_(spec.name) {
  if (spec.name.empty()) throw InputError(fieldPrefix + ".name", "\"\"", "a deformable body needs a name");
  requirePositive(fieldPrefix + ".total_mass", spec.total_mass);
  requireNonNegative(fieldPrefix + ".node_damping", spec.node_damping);
  if (std::isnan(spec.break_force) || !(spec.break_force > 0.0)) {
    throw InputError(fieldPrefix + ".break_force", formatValue(spec.break_force), "must be positive (or infinite)");
  }
  if (std::isnan(spec.break_strain) || !(spec.break_strain > 0.0)) {
    throw InputError(fieldPrefix + ".break_strain", formatValue(spec.break_strain), "must be positive (or infinite)");
  }
  MassSpringTopology topology = buildMassSpringTopology(spec, fieldPrefix);
  const std::size_t n = topology.nodes.size();
  if (n < 2) throw InputError(fieldPrefix + ".nodes", std::to_string(n) + " nodes", "a body needs at least two nodes");
  surface_ = DeformableSurface(n, std::move(topology.triangles), spec.material, fieldPrefix);
  surface_.positions() = topology.nodes;
  reference_ = std::move(topology.nodes);
  springs_ = std::move(topology.springs);
  intact_.assign(springs_.size(), 1);
  node_force_.assign(n, Vec3::Zero());
  node_mass_ = spec.total_mass / static_cast<double>(n);
  node_damping_ = spec.node_damping;
  break_force_ = spec.break_force;
  break_strain_ = spec.break_strain;

  constraints_ = NodeConstraints(
      spec, reference_, [](std::uint32_t id) { return std::optional<std::uint32_t>(id); },
      "node index out of range (the body has " + std::to_string(n) + " nodes)", ConstraintOverlap::kError,
      fieldPrefix);

  // Which triangles each spring supports: a spring along one of a triangle's edges.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> trianglesOfEdge;
  const auto& triangles = surface_.triangles();
  for (std::uint32_t t = 0; t < triangles.size(); ++t) {
    for (int e = 0; e < 3; ++e) trianglesOfEdge[std::minmax(triangles[t][e], triangles[t][(e + 1) % 3])].push_back(t);
  }
  spring_triangle_offsets_.assign(1, 0);
  for (const SpringSpec& spring : springs_) {
    const auto it = trianglesOfEdge.find(std::minmax(spring.a, spring.b));
    if (it != trianglesOfEdge.end()) {
      spring_triangles_.insert(spring_triangles_.end(), it->second.begin(), it->second.end());
    }
    spring_triangle_offsets_.push_back(static_cast<std::uint32_t>(spring_triangles_.size()));
  }
  // Springs built with another rest length than their initial distance act from the first half kick on.
  addSpringForces(false, 0.0);
}

void MassSpringBody::beginStep(double dt, const Vec3& gravity) {
  std::vector<Vec3>& x = surface_.positions();
  std::vector<Vec3>& v = surface_.velocities();
  const double halfStepPerMass = 0.5 * dt / node_mass_;
  for (std::size_t node = 0; node < x.size(); ++node) {
    if (constraints_.role(node) != NodeRole::kFree) continue;
    v[node] += halfStepPerMass * node_force_[node] + 0.5 * dt * gravity;
    x[node] += v[node] * dt;
  }
  constraints_.advance(dt);
  constraints_.forEachDriven([&](std::uint32_t node, const Vec3& position, const Vec3& velocity) {
    x[node] = position;
    v[node] = velocity;
  });
}

void MassSpringBody::addSpringForces(bool tear, double time) {
  const std::vector<Vec3>& x = surface_.positions();
  const std::vector<Vec3>& v = surface_.velocities();
  // Without a strain limit no strain exceeds it: the division is left out of the loop.
  const bool strainLimited = break_strain_ < std::numeric_limits<double>::infinity();
  for (std::uint32_t s = 0; s < springs_.size(); ++s) {
    if (intact_[s] == 0) continue;
    const SpringSpec& spring = springs_[s];
    const Vec3 d = x[spring.b] - x[spring.a];
    const double length = d.norm();
    const Vec3 e = length > 0.0 ? Vec3(d / length) : Vec3::Zero();
    const double stretch = length - spring.rest_length;
    const double magnitude = spring.stiffness * stretch + spring.damping * (v[spring.b] - v[spring.a]).dot(e);
    if (tear && (std::abs(magnitude) > break_force_ ||
                 (strainLimited && std::abs(stretch) / spring.rest_length > break_strain_))) {
      const double strain = std::abs(stretch) / spring.rest_length;
      intact_[s] = 0;
      broken_.push_back({s, time, 0.5 * (x[spring.a] + x[spring.b]), std::abs(magnitude), strain});
      deactivateTrianglesOf(s);
      continue;
    }
    node_force_[spring.a] += magnitude * e;
    node_force_[spring.b] -= magnitude * e;
  }
}

void MassSpringBody::deactivateTrianglesOf(std::uint32_t spring) {
  for (std::uint32_t k = spring_triangle_offsets_[spring]; k < spring_triangle_offsets_[spring + 1]; ++k) {
    surface_.setActive(spring_triangles_[k], false);
  }
}

void MassSpringBody::endStep(double dt, const Vec3& gravity) {
  const std::vector<Vec3>& x = surface_.positions();
  std::vector<Vec3>& v = surface_.velocities();
  node_force_ = surface_.nodeForces();
  ++steps_;
  addSpringForces(true, static_cast<double>(steps_) * dt);
  if (node_damping_ > 0.0) {
    for (std::size_t node = 0; node < x.size(); ++node) {
      if (constraints_.role(node) == NodeRole::kFree) node_force_[node] -= node_damping_ * node_mass_ * v[node];
    }
  }
  const double halfStepPerMass = 0.5 * dt / node_mass_;
  NodeReaction fixed;
  NodeReaction driven;
  const DrivenPose& pose = constraints_.pose();
  for (std::size_t node = 0; node < x.size(); ++node) {
    const NodeRole role = constraints_.role(node);
    if (role == NodeRole::kFree) {
      v[node] += halfStepPerMass * node_force_[node] + 0.5 * dt * gravity;
      continue;
    }
    if (role == NodeRole::kFixed) {
      const Vec3 r = -node_force_[node] - node_mass_ * gravity;
      fixed.force += r;
      fixed.torque += x[node].cross(r);
    } else {
      const Vec3 arm = x[node] - pose.position;
      const Vec3 acceleration = pose.angular_velocity.cross(pose.angular_velocity.cross(arm));
      const Vec3 r = node_mass_ * acceleration - node_force_[node] - node_mass_ * gravity;
      driven.force += r;
      driven.torque += arm.cross(r);
    }
  }
  constraints_.setReactions(fixed, driven);
}

MassSpringBody::StableStep MassSpringBody::stableStep() const {
  std::vector<double> stiffnessSum(reference_.size(), 0.0);
  std::vector<double> dampingSum(reference_.size(), 0.0);
  for (std::size_t s = 0; s < springs_.size(); ++s) {
    if (intact_[s] == 0) continue;
    for (const std::uint32_t node : {springs_[s].a, springs_[s].b}) {
      stiffnessSum[node] += springs_[s].stiffness;
      dampingSum[node] += springs_[s].damping;
    }
  }
  StableStep out;
  double largestDamping = 0.0;
  for (std::size_t node = 0; node < stiffnessSum.size(); ++node) {
    if (constraints_.role(node) != NodeRole::kFree) continue;
    if (stiffnessSum[node] > out.stiffness_sum) {
      out.stiffness_sum = stiffnessSum[node];
      out.node = node;
    }
    largestDamping = std::max(largestDamping, dampingSum[node]);
  }
  if (!(out.stiffness_sum > 0.0)) return out;
  // Gershgorin: the eigenvalues of M^-1 K are at most 2 sum k / m, those of M^-1 C at most 2 sum c / m.
  const double omega = std::sqrt(2.0 * out.stiffness_sum / node_mass_);
  out.damping_ratio = (largestDamping / node_mass_ + 0.5 * node_damping_) / omega;
  out.step = 2.0 / omega * (std::sqrt(1.0 + out.damping_ratio * out.damping_ratio) - out.damping_ratio);
  return out;
}

double MassSpringBody::criticalTimeStep() const { return stableStep().step; }

std::string MassSpringBody::criticalTimeStepReason() const {
  const StableStep stable = stableStep();
  if (!(stable.stiffness_sum > 0.0)) return "no free node has a spring";
  return "stiffest node " + std::to_string(stable.node) + ": sum of spring stiffness " +
         formatValue(stable.stiffness_sum) + " N/m, node mass " + formatValue(node_mass_) +
         " kg, damping ratio bound " + formatValue(stable.damping_ratio) +
         "; dt < 2 / omega (sqrt(1 + zeta^2) - zeta), omega^2 = 2 sum k / m";
}

void MassSpringBody::setDrivenPose(const Vec3& position, const Quat& orientation, const Vec3& linearVelocity,
                                   const Vec3& angularVelocity) {
  constraints_.setPose({position, orientation, linearVelocity, angularVelocity}, name_);
}

bool MassSpringBody::hasDrivenNodes() const { return !constraints_.driven().empty(); }
NodeReaction MassSpringBody::drivenReaction() const { return constraints_.drivenReaction(); }
NodeReaction MassSpringBody::fixedReaction() const { return constraints_.fixedReaction(); }
std::size_t MassSpringBody::nodeCount() const { return reference_.size(); }
Vec3 MassSpringBody::nodePosition(std::size_t node) const { return surface_.positions().at(node); }
Vec3 MassSpringBody::nodeDisplacement(std::size_t node) const {
  return surface_.positions().at(node) - reference_.at(node);
}
Vec3 MassSpringBody::nodeVelocity(std::size_t node) const { return surface_.velocities().at(node); }
std::uint64_t MassSpringBody::brokenCount() const { return broken_.size(); }
double MassSpringBody::totalMass() const { return node_mass_ * static_cast<double>(reference_.size()); }

double MassSpringBody::kineticEnergy() const {
  double sum = 0.0;
  for (const Vec3& v : surface_.velocities()) sum += v.squaredNorm();
  return 0.5 * node_mass_ * sum;
}

double MassSpringBody::springEnergy() const {
  const std::vector<Vec3>& x = surface_.positions();
  double energy = 0.0;
  for (std::size_t s = 0; s < springs_.size(); ++s) {
    if (intact_[s] == 0) continue;
    const double stretch = (x[springs_[s].b] - x[springs_[s].a]).norm() - springs_[s].rest_length;
    energy += 0.5 * springs_[s].stiffness * stretch * stretch;
  }
  return energy;
}

void MassSpringBody::save(StateWriter& out) const {
  out.write(steps_);
  out.writeVector(surface_.positions());
  out.writeVector(surface_.velocities());
  out.writeVector(node_force_);
  out.writeVector(intact_);
  out.writeVector(broken_);
  constraints_.save(out);
}

void MassSpringBody::restore(StateReader& in) {
  const auto steps = in.read<std::uint64_t>();
  std::vector<Vec3> positions = in.readVector<Vec3>();
  std::vector<Vec3> velocities = in.readVector<Vec3>();
  std::vector<Vec3> forces = in.readVector<Vec3>();
  std::vector<char> intact = in.readVector<char>();
  std::vector<BrokenSpring> broken = in.readVector<BrokenSpring>();
  const std::string nodes = "mass-spring body " + name_ + ": node count differs from the scene's";
  requireSameLength(in, positions, reference_, nodes);
  requireSameLength(in, velocities, reference_, nodes);
  requireSameLength(in, forces, reference_, nodes);
  requireSameLength(in, intact, springs_, "mass-spring body " + name_ + ": spring count differs from the scene's");
  for (const BrokenSpring& b : broken) {
    if (b.spring >= springs_.size() || intact[b.spring] != 0) {
      in.fail(std::to_string(b.spring), "mass-spring body " + name_ + ": broken spring not marked broken");
    }
  }
  constraints_.restore(in);
  steps_ = steps;
  surface_.positions() = std::move(positions);
  surface_.velocities() = std::move(velocities);
  node_force_ = std::move(forces);
  intact_ = std::move(intact);
  broken_ = std::move(broken);
  // The surface's active flags follow from the intact flags (the tearing rule).
  for (std::size_t t = 0; t < surface_.triangles().size(); ++t) surface_.setActive(t, true);
  for (std::uint32_t s = 0; s < springs_.size(); ++s) {
    if (intact_[s] != 0) continue;
    deactivateTrianglesOf(s);
  }
}

}  // namespace demlink::core
