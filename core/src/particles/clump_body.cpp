/// Rigid-body integration of clumps (see clump_body.hpp for the scheme).
#include "demlink/core/particles/clump_body.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "demlink/core/state/state_stream.hpp"

namespace demlink::core {
namespace {

/// dq/dt = 1/2 (0, w) q for the angular velocity w [rad/s].
Eigen::Vector4d quaternionRate(const Quat& q, const Vec3& w) {
  const Quat product = Quat(0.0, w.x(), w.y(), w.z()) * q;
  return 0.5 * product.coeffs();
}

Quat fromCoeffs(const Eigen::Vector4d& c) {
  Quat q;
  q.coeffs() = c;
  return q;
}

}  // namespace

Vec3 ClumpBody::angularVelocityAt(const Quat& q) const {
  const Vec3 bodyMomentum = q.conjugate() * angular_momentum;
  return q * Vec3(bodyMomentum.cwiseQuotient(inertia));
}

double ClumpBody::kineticEnergy() const {
  return 0.5 * mass * velocity.squaredNorm() + 0.5 * angular_momentum.dot(angularVelocity());
}

void kickClump(ClumpBody& body, const Vec3& gravity, double h) {
  body.velocity += (body.force / body.mass + gravity) * h;
  body.angular_momentum += body.torque * h;
}

void driftClump(ClumpBody& body, double dt) {
  body.position += body.velocity * dt;
  const double angle = body.angularVelocity().norm() * dt;
  if (angle == 0.0) return;
  // Bounded so that a blown-up state (huge or non-finite w) cannot stall the step.
  const int substeps = angle < kMaxSubsteps * kMaxSubstepAngle
                           ? std::max(1, static_cast<int>(std::ceil(angle / kMaxSubstepAngle)))
                           : kMaxSubsteps;
  const double h = dt / substeps;
  Eigen::Vector4d q = body.orientation.coeffs();
  for (int s = 0; s < substeps; ++s) {
    const Eigen::Vector4d k1 = quaternionRate(fromCoeffs(q), body.angularVelocityAt(fromCoeffs(q)));
    const Quat q2 = fromCoeffs(q + 0.5 * h * k1);
    const Eigen::Vector4d k2 = quaternionRate(q2, body.angularVelocityAt(q2));
    const Quat q3 = fromCoeffs(q + 0.5 * h * k2);
    const Eigen::Vector4d k3 = quaternionRate(q3, body.angularVelocityAt(q3));
    const Quat q4 = fromCoeffs(q + h * k3);
    const Eigen::Vector4d k4 = quaternionRate(q4, body.angularVelocityAt(q4));
    q += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    q.normalize();
  }
  body.orientation = fromCoeffs(q);
}

void gatherClumpForces(ClumpBody& body, const ParticleArrays& particles) {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
  for (const std::uint32_t slot : body.member_slots) {
    const Vec3& f = particles.force[slot];
    force += f;
    torque += (particles.position[slot] - body.position).cross(f) + particles.torque[slot];
  }
  body.force = force;
  body.torque = torque;
}

void placeClumpMembers(const ClumpBody& body, const ClumpTemplate& shape, ParticleArrays& particles,
                       bool positions) {
  const Mat3 rotation = body.orientation.toRotationMatrix();
  const Vec3 w = body.angularVelocity();
  const std::vector<ClumpSphere>& spheres = shape.bodySpheres();
  for (std::size_t k = 0; k < body.member_slots.size(); ++k) {
    const std::uint32_t slot = body.member_slots[k];
    const Vec3 arm = rotation * spheres[k].offset;
    if (positions) particles.position[slot] = body.position + arm;
    particles.velocity[slot] = body.velocity + w.cross(arm);
    particles.angular_velocity[slot] = w;
  }
}

void ClumpBody::save(StateWriter& out) const {
  out.write(id);
  out.write(template_index);
  out.write(mass);
  out.write(inertia);
  out.write(position);
  out.write(velocity);
  out.write(orientation);
  out.write(angular_momentum);
  out.write(force);
  out.write(torque);
  out.writeVector(member_slots);
}

void ClumpBody::restore(StateReader& in, const std::vector<ClumpTemplate>& templates, std::size_t slotCount) {
  ClumpBody staged;
  staged.id = in.read<std::uint64_t>();
  staged.template_index = in.read<std::uint32_t>();
  staged.mass = in.read<double>();
  staged.inertia = in.read<Vec3>();
  staged.position = in.read<Vec3>();
  staged.velocity = in.read<Vec3>();
  staged.orientation = in.read<Quat>();
  staged.angular_momentum = in.read<Vec3>();
  staged.force = in.read<Vec3>();
  staged.torque = in.read<Vec3>();
  staged.member_slots = in.readVector<std::uint32_t>();
  if (staged.template_index >= templates.size()) {
    in.fail(std::to_string(staged.template_index), "clump template index out of range");
  }
  requireEqual(in, "member count of clump " + std::to_string(staged.id),
               static_cast<std::uint64_t>(staged.member_slots.size()),
               static_cast<std::uint64_t>(templates[staged.template_index].spheres().size()));
  requireIndices(in, staged.member_slots, slotCount, "clump member slot");
  *this = std::move(staged);
}

void saveClumps(StateWriter& out, const std::vector<ClumpBody>& clumps) {
  out.write<std::uint64_t>(clumps.size());
  for (const ClumpBody& body : clumps) body.save(out);
}

std::vector<ClumpBody> restoreClumps(StateReader& in, const std::vector<ClumpTemplate>& templates,
                                     std::size_t slotCount) {
  const auto count = in.read<std::uint64_t>();
  // Each body needs well over 64 bytes: a corrupt count cannot allocate much.
  if (count > in.remaining() / 64) in.fail(std::to_string(count), "clump count exceeds the section");
  std::vector<ClumpBody> clumps(count);
  for (ClumpBody& body : clumps) body.restore(in, templates, slotCount);
  return clumps;
}

}  // namespace demlink::core
