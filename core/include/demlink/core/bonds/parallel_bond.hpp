#pragma once
/// One parallel bond between two spheres, after Potyondy and Cundall, "A bonded-particle
/// model for rock", Int. J. Rock Mech. Min. Sci. 41 (2004) 1329-1364,
/// doi:10.1016/j.ijrmms.2004.09.011 (docs/physics.md, "Parallel bonds").
///
/// The bond is a disc of cement of radius Rb = lambda min(Ra, Rb) between the spheres,
/// A = pi Rb^2, I = pi Rb^4 / 4, J = pi Rb^4 / 2, with elastic stiffness per area
/// kn, ks [Pa/m]. Its force and moment grow by increments of the relative motion at the
/// bond's centre each step (a bond made at rest carries nothing):
///   dFn = kn A  dUn        dFs = ks A  dUs        (dU: relative displacement, v dt)
///   dMt = ks J  dtheta_n   dMb = kn I  dtheta_s   (dtheta: relative rotation, w dt)
/// The shear force and bending moment are kept in the bond plane: before each increment
/// they are projected onto the new plane and scaled back to their length. The largest
/// stresses on the bond's rim are
///   sigma = Fn / A + |Mb| Rb / I      (tension positive)
///   tau   = |Fs| / A + |Mt| Rb / J
/// and the bond breaks, for good, when sigma >= tensile_strength or tau >= shear_strength;
/// it then carries nothing and the pair is left to the contact law (which acts on a
/// touching pair all along, bonded or not: the bond is parallel to the contact).
#include <cstdint>
#include <string>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

/// What a scene chose for its bonds.
struct ParallelBondProperties {
  double radius_multiplier = 1.0;          ///< lambda: bond radius / smaller sphere radius [-], in (0, 1]
  double normal_stiffness_per_area = 0.0;  ///< kn [Pa/m], > 0
  double shear_stiffness_per_area = 0.0;   ///< ks [Pa/m], > 0
  double tensile_strength = 0.0;           ///< [Pa], > 0
  double shear_strength = 0.0;             ///< cohesion [Pa], > 0
  double gap_tolerance = 0.0;              ///< largest surface gap of a pair that is bonded [m], >= 0

  /// Throws InputError naming fieldPrefix + ".<field>" and the value unless every field
  /// is finite and in its range.
  void validate(const std::string& fieldPrefix) const;
};

/// The cross-section of a bond between spheres of radii ra and rb.
struct BondSection {
  double radius = 0.0;  ///< Rb [m]
  double area = 0.0;    ///< A [m^2]
  double inertia = 0.0; ///< I, second moment of area about a diameter [m^4]
  double polar = 0.0;   ///< J, polar moment [m^4]

  [[nodiscard]] static BondSection of(double radiusMultiplier, double ra, double rb);
};

/// A bond's state; the force and moments are those acting on particle a (b feels the
/// opposite ones).
struct ParallelBond {
  std::uint64_t id_a = 0;  ///< stable particle ids, id_a < id_b
  std::uint64_t id_b = 0;
  std::uint32_t slot_a = 0;  ///< current slots (kept up to date by BondSet)
  std::uint32_t slot_b = 0;
  std::uint32_t rule = 0;    ///< index of the BondRule that made it
  bool broken = false;
  Vec3 normal = Vec3::UnitX();            ///< unit vector a -> b at the last update [-]
  double normal_force = 0.0;              ///< Fn, tension positive [N]
  Vec3 shear_force = Vec3::Zero();        ///< Fs, on a, in the bond plane [N]
  double twisting_moment = 0.0;           ///< Mt, on a, about `normal` [N m]
  Vec3 bending_moment = Vec3::Zero();     ///< Mb, on a, in the bond plane [N m]
};

/// The kinematics of the two particles at the end of a step.
struct BondEnds {
  Vec3 position_a, position_b;      ///< [m]
  Vec3 velocity_a, velocity_b;      ///< [m/s]
  Vec3 spin_a, spin_b;              ///< [rad/s]
  double radius_a = 0.0, radius_b = 0.0;  ///< [m]
};

/// What the bond does to its particles this step (b: minus force_a).
struct BondLoad {
  Vec3 force_a = Vec3::Zero();   ///< [N]
  Vec3 torque_a = Vec3::Zero();  ///< about a's centre [N m]
  Vec3 torque_b = Vec3::Zero();  ///< about b's centre [N m]
};

/// Adds one step's increments (dt [s]) to `bond`, checks its strength and returns the
/// load on its particles; a bond that breaks now is marked broken, zeroed, and loads
/// nothing. A broken bond loads nothing.
BondLoad advanceParallelBond(ParallelBond& bond, const ParallelBondProperties& properties, const BondEnds& ends,
                             double dt);

/// The largest tensile and shear stress on the bond's rim [Pa].
struct BondStress {
  double tensile = 0.0;
  double shear = 0.0;
};
[[nodiscard]] BondStress bondStress(const ParallelBond& bond, const BondSection& section);

/// Elastic energy stored in the bond [J]:
/// Fn^2 / (2 kn A) + |Fs|^2 / (2 ks A) + Mt^2 / (2 ks J) + |Mb|^2 / (2 kn I).
[[nodiscard]] double bondStrainEnergy(const ParallelBond& bond, const ParallelBondProperties& properties,
                                      const BondSection& section);

}  // namespace demlink::core
