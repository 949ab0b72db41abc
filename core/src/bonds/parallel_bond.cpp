/// One parallel bond's law (contract and equations in parallel_bond.hpp).
#include "demlink/core/bonds/parallel_bond.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

/// `v` projected onto the plane of unit normal `n`, with its length kept: the bond's
/// in-plane vectors follow the plane as the pair turns. One square root of the ratio of
/// the squared lengths (the step sits on the bond stage's chain of dependent operations).
Vec3 keepInPlane(const Vec3& v, const Vec3& n) {
  const double length2 = v.squaredNorm();
  if (length2 == 0.0) return v;
  const Vec3 projected = v - n.dot(v) * n;
  const double projected2 = projected.squaredNorm();
  if (projected2 == 0.0) return Vec3::Zero();
  return projected * std::sqrt(length2 / projected2);
}

}  // namespace

void ParallelBondProperties::validate(const std::string& fieldPrefix) const {
  requireHalfOpenRange(fieldPrefix + ".radius_multiplier", radius_multiplier, 0.0, 1.0);
  requirePositive(fieldPrefix + ".normal_stiffness_per_area", normal_stiffness_per_area);
  requirePositive(fieldPrefix + ".shear_stiffness_per_area", shear_stiffness_per_area);
  requirePositive(fieldPrefix + ".tensile_strength", tensile_strength);
  requirePositive(fieldPrefix + ".shear_strength", shear_strength);
  requireNonNegative(fieldPrefix + ".gap_tolerance", gap_tolerance);
}

BondSection BondSection::of(double radiusMultiplier, double ra, double rb) {
  BondSection s;
  s.radius = radiusMultiplier * std::min(ra, rb);
  const double r2 = s.radius * s.radius;
  s.area = std::numbers::pi * r2;
  s.inertia = 0.25 * std::numbers::pi * r2 * r2;
  s.polar = 2.0 * s.inertia;
  return s;
}

namespace {

BondStress stressOf(double normalForce, const Vec3& shearForce, double twistingMoment, const Vec3& bendingMoment,
                    const BondSection& section) {
  BondStress s;
  s.tensile = normalForce / section.area + bendingMoment.norm() * section.radius / section.inertia;
  s.shear = shearForce.norm() / section.area + std::abs(twistingMoment) * section.radius / section.polar;
  return s;
}

}  // namespace

BondLoad advanceParallelBond(ParallelBond& bond, const ParallelBondProperties& properties, const BondEnds& ends,
                             double dt) {
  BondLoad load;
  if (bond.broken) return load;
  // The bond's state goes through locals and is stored once at the end: fields stored in
  // pieces and read back as vectors stall the processor's store forwarding.
  const BondSection section = BondSection::of(properties.radius_multiplier, ends.radius_a, ends.radius_b);
  const Vec3 branch = ends.position_b - ends.position_a;
  const double distance = branch.norm();
  const Vec3 n = distance > 0.0 ? Vec3(branch * (1.0 / distance)) : bond.normal;
  Vec3 shearForce = keepInPlane(bond.shear_force, n);
  Vec3 bendingMoment = keepInPlane(bond.bending_moment, n);

  // The bond's centre: the middle of the gap (of the overlap when they overlap).
  const double halfGap = 0.5 * (distance - ends.radius_a - ends.radius_b);
  const Vec3 armA = (ends.radius_a + halfGap) * n;   // centre of a -> bond centre
  const Vec3 armB = -(ends.radius_b + halfGap) * n;  // centre of b -> bond centre
  const Vec3 relative =
      (ends.velocity_b + ends.spin_b.cross(armB)) - (ends.velocity_a + ends.spin_a.cross(armA));
  const double normalSpeed = relative.dot(n);
  const Vec3 shearVelocity = relative - normalSpeed * n;
  const Vec3 relativeSpin = ends.spin_b - ends.spin_a;
  const double twistRate = relativeSpin.dot(n);
  const Vec3 bendRate = relativeSpin - twistRate * n;

  const double kn = properties.normal_stiffness_per_area;
  const double ks = properties.shear_stiffness_per_area;
  const double normalForce = bond.normal_force + kn * section.area * normalSpeed * dt;
  shearForce += ks * section.area * dt * shearVelocity;
  const double twistingMoment = bond.twisting_moment + ks * section.polar * twistRate * dt;
  bendingMoment += kn * section.inertia * dt * bendRate;

  bond.normal = n;
  const BondStress stress = stressOf(normalForce, shearForce, twistingMoment, bendingMoment, section);
  if (stress.tensile >= properties.tensile_strength || stress.shear >= properties.shear_strength) {
    bond.broken = true;
    bond.normal_force = 0.0;
    bond.shear_force.setZero();
    bond.twisting_moment = 0.0;
    bond.bending_moment.setZero();
    return load;
  }
  bond.normal_force = normalForce;
  bond.shear_force = shearForce;
  bond.twisting_moment = twistingMoment;
  bond.bending_moment = bendingMoment;
  const Vec3 moment = twistingMoment * n + bendingMoment;
  load.force_a = normalForce * n + shearForce;
  load.torque_a = armA.cross(shearForce) + moment;
  load.torque_b = armB.cross(-shearForce) - moment;
  return load;
}

BondStress bondStress(const ParallelBond& bond, const BondSection& section) {
  return stressOf(bond.normal_force, bond.shear_force, bond.twisting_moment, bond.bending_moment, section);
}

double bondStrainEnergy(const ParallelBond& bond, const ParallelBondProperties& properties,
                        const BondSection& section) {
  const double kn = properties.normal_stiffness_per_area;
  const double ks = properties.shear_stiffness_per_area;
  return bond.normal_force * bond.normal_force / (2.0 * kn * section.area) +
         bond.shear_force.squaredNorm() / (2.0 * ks * section.area) +
         bond.twisting_moment * bond.twisting_moment / (2.0 * ks * section.polar) +
         bond.bending_moment.squaredNorm() / (2.0 * kn * section.inertia);
}

}  // namespace demlink::core
