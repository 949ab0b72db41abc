/// One parallel bond's law (contract and equations in parallel_bond.hpp).
#include "demlink/core/bonds/parallel_bond.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

/// `v` projected onto the plane of unit normal `n`, with its length kept: the bond's
/// in-plane vectors follow the plane as the pair turns.
Vec3 keepInPlane(const Vec3& v, const Vec3& n) {
  const double length = v.norm();
  if (length == 0.0) return v;
  const Vec3 projected = v - n.dot(v) * n;
  const double projectedLength = projected.norm();
  if (projectedLength == 0.0) return Vec3::Zero();
  return projected * (length / projectedLength);
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

BondLoad advanceParallelBond(ParallelBond& bond, const ParallelBondProperties& properties, const BondEnds& ends,
                             double dt) {
  BondLoad load;
  if (bond.broken) return load;
  const BondSection section = BondSection::of(properties.radius_multiplier, ends.radius_a, ends.radius_b);
  const Vec3 branch = ends.position_b - ends.position_a;
  const double distance = branch.norm();
  const Vec3 n = distance > 0.0 ? Vec3(branch / distance) : bond.normal;
  bond.normal = n;
  bond.shear_force = keepInPlane(bond.shear_force, n);
  bond.bending_moment = keepInPlane(bond.bending_moment, n);

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
  bond.normal_force += kn * section.area * normalSpeed * dt;
  bond.shear_force += ks * section.area * dt * shearVelocity;
  bond.twisting_moment += ks * section.polar * twistRate * dt;
  bond.bending_moment += kn * section.inertia * dt * bendRate;

  const BondStress stress = bondStress(bond, section);
  if (stress.tensile >= properties.tensile_strength || stress.shear >= properties.shear_strength) {
    bond.broken = true;
    bond.normal_force = 0.0;
    bond.shear_force.setZero();
    bond.twisting_moment = 0.0;
    bond.bending_moment.setZero();
    return load;
  }
  const Vec3 moment = bond.twisting_moment * n + bond.bending_moment;
  load.force_a = bond.normal_force * n + bond.shear_force;
  load.torque_a = armA.cross(bond.shear_force) + moment;
  load.torque_b = armB.cross(-bond.shear_force) - moment;
  return load;
}

BondStress bondStress(const ParallelBond& bond, const BondSection& section) {
  BondStress s;
  s.tensile = bond.normal_force / section.area + bond.bending_moment.norm() * section.radius / section.inertia;
  s.shear = bond.shear_force.norm() / section.area + std::abs(bond.twisting_moment) * section.radius / section.polar;
  return s;
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
