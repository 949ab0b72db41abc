#pragma once
/// A bulk material as the contact laws see it. All values SI.
#include <string>

namespace demlink::core {

struct Material {
  std::string name;
  double density = 2500.0;            ///< [kg/m^3]
  double youngs_modulus = 1.0e7;      ///< [Pa] (the "DEM" modulus, often reduced vs. the bulk value)
  double poisson_ratio = 0.3;         ///< [-], in (-1, 0.5)
  double restitution = 0.5;           ///< coefficient of restitution e [-], in (0, 1]
  double sliding_friction = 0.5;      ///< Coulomb coefficient mu [-], >= 0
  double rolling_friction = 0.0;      ///< EPSD rolling coefficient mu_r [-], >= 0 (0 = off)
  /// Cohesion energy density k_c [J/m^3 = Pa], >= 0 (0 = dry): a contact of overlap
  /// area A attracts with k_c A (docs/physics.md "Cohesion").
  double cohesion_energy_density = 0.0;
  /// A wall material that does not deform: pair mixing drops its compliance, so
  /// the particle alone sets E* = E_p / (1 - nu_p^2) and G* = G_p / (2 - nu_p).
  /// Set by World for the twin of a rigid wall's material, never by a scene.
  bool rigid = false;

  /// Throws InputError naming `fieldPrefix + ".<field>"` for the first invalid value.
  void validate(const std::string& fieldPrefix) const;

  /// Shear modulus G = E / (2 (1 + nu)) [Pa].
  [[nodiscard]] double shearModulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
};

}  // namespace demlink::core
