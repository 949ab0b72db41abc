#pragma once
/// Coarse graining: one simulated parcel of radius alpha R stands for alpha^3 grains of
/// radius R, so a bed of the same bulk mass needs alpha^3 fewer particles.
///
/// The scaling law (docs/accuracy.md "Coarse graining"), after Bierwisch, Kraft, Riedel
/// and Moseler, "Three-dimensional discrete element models for the granular statics and
/// dynamics of powders in cavity filling", J. Mech. Phys. Solids 57 (2009) 10-31,
/// doi:10.1016/j.jmps.2008.10.006: keep density, Young's modulus, Poisson ratio,
/// restitution and the friction coefficients, and scale every length by alpha.
///   - Hertz: F = 4/3 E* sqrt(R*) delta^{3/2}, so the contact stress F / R^2 depends on
///     delta / R only; the parcels deform by the same fraction of their size under the same
///     bulk stress, and the same restitution gives the same dissipated energy fraction.
///   - Linear spring: k_n must grow like alpha (k_n ~ E R) to keep delta / R. A stiffness
///     derived from Hertz (SimulationSettings::linear_normal_stiffness = 0) follows by
///     itself; an explicit one is scaled by linearStiffness().
///   - Cohesion, the simplified JKR law F = k_c A (contact area A = pi a^2, a^2 ~ 2 R* delta):
///     k_c is kept (cohesionEnergyDensity()). At the same delta / R the area grows like
///     alpha^2, as every other contact force does, so the bed Bond number F_coh / (rho g h
///     d^2) -- cohesive force against the overburden a contact carries at depth h -- is the
///     grains', and so are the cohesive energy density U_coh / V = k_c * O((delta / R)^2)
///     and the Rumpf tensile strength ~ F_coh / d^2 (Bierwisch et al.'s criterion: every
///     energy density kept). The single-parcel Bond number F_coh / (m g) falls like 1 / alpha:
///     a parcel is as strong as the alpha^2 grain contacts across its face, not as one grain.
///     Keeping that one instead (k_c ~ alpha) would make the bulk alpha times stronger.
/// The critical time step grows like alpha (contact duration ~ R), so the cost of a
/// simulated second falls like alpha^-4; what is lost is every effect of the grain size
/// against the geometry (orifice / grain, wall / grain ratios).
#include <cstddef>
#include <string>

namespace demlink::core {

struct CoarseGraining {
  double factor = 1.0;  ///< alpha: parcel radius / grain radius [-], >= 1

  /// Throws InputError naming `field` unless the factor is finite and >= 1.
  void validate(const std::string& field) const;
  /// Parcel radius for a grain radius [m].
  [[nodiscard]] double radius(double grainRadius) const { return factor * grainRadius; }
  /// Parcels that carry the mass of `grains` grains (rounded, at least 1) [-].
  [[nodiscard]] std::size_t count(std::size_t grains) const;
  /// Linear-law normal stiffness for the parcels from the grains' one [N/m].
  [[nodiscard]] double linearStiffness(double grainStiffness) const { return factor * grainStiffness; }
  /// Cohesion energy density k_c [J/m^3] of the simplified JKR law for the parcels from the
  /// grains' one: kept (see above; docs/accuracy.md "Coarse graining" derives it).
  [[nodiscard]] double cohesionEnergyDensity(double grainValue) const { return grainValue; }
};

}  // namespace demlink::core
