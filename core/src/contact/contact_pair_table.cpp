#include "demlink/core/contact/contact_pair_table.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "demlink/core/contact/contact_law_registry.hpp"
#include "demlink/core/base/input_error.hpp"

namespace demlink::core {

double effectiveYoungsModulus(const Material& a, const Material& b) {
  // A rigid side has no compliance (1/E = 0).
  auto compliance = [](const Material& m) {
    return m.rigid ? 0.0 : (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus;
  };
  return 1.0 / (compliance(a) + compliance(b));
}

double effectiveShearModulus(const Material& a, const Material& b) {
  auto compliance = [](const Material& m) { return m.rigid ? 0.0 : (2.0 - m.poisson_ratio) / m.shearModulus(); };
  return 1.0 / (compliance(a) + compliance(b));
}

void PairOverride::validate(const std::string& fieldPrefix) const {
  if (restitution) requireHalfOpenRange(fieldPrefix + ".restitution", *restitution, 0.0, 1.0);
  if (sliding_friction) requireNonNegative(fieldPrefix + ".sliding_friction", *sliding_friction);
  if (rolling_friction) requireNonNegative(fieldPrefix + ".rolling_friction", *rolling_friction);
  if (cohesion_energy_density) {
    requireNonNegative(fieldPrefix + ".cohesion_energy_density", *cohesion_energy_density);
  }
}

namespace {

std::vector<std::uint32_t> allMaterials(std::size_t count) {
  std::vector<std::uint32_t> all(count);
  std::iota(all.begin(), all.end(), 0u);
  return all;
}

}  // namespace

ContactPairTable::ContactPairTable(const std::vector<Material>& materials, ContactModel model,
                                   const LinearStiffnessReference& linearReference,
                                   const std::vector<PairOverrideEntry>& overrides)
    : ContactPairTable(materials, model, linearReference, overrides, allMaterials(materials.size())) {}

ContactPairTable::ContactPairTable(const std::vector<Material>& materials, ContactModel model,
                                   const LinearStiffnessReference& linearReference,
                                   const std::vector<PairOverrideEntry>& overrides,
                                   const std::vector<std::uint32_t>& used)
    : count_(static_cast<std::uint32_t>(used.size())),
      slot_(materials.size(), kNoSlot),
      used_(used),
      pairs_(used.size() * used.size()) {
  for (std::uint32_t row = 0; row < count_; ++row) slot_[used[row]] = row;
  // Overrides by unordered pair (lower index first); scenes have few, a map is plenty.
  std::map<std::pair<std::uint32_t, std::uint32_t>, const PairOverride*> overrideOf;
  for (const PairOverrideEntry& entry : overrides) {
    overrideOf[std::minmax(entry.material_a, entry.material_b)] = &entry.values;
  }
  const ContactLawEntry& law = contactLaw(model);
  std::map<double, double> dampingOfRestitution;  // calibration is ~ms each; reuse across pairs
  for (std::uint32_t i = 0; i < count_; ++i) {
    for (std::uint32_t j = i; j < count_; ++j) {
      const Material& a = materials[used[i]];
      const Material& b = materials[used[j]];
      ContactPairParams p;
      p.effective_youngs = effectiveYoungsModulus(a, b);
      p.effective_shear = effectiveShearModulus(a, b);
      // Different materials: arithmetic means, unless the scene overrides the pair.
      p.restitution = 0.5 * (a.restitution + b.restitution);
      p.sliding_friction = 0.5 * (a.sliding_friction + b.sliding_friction);
      p.rolling_friction = 0.5 * (a.rolling_friction + b.rolling_friction);
      p.cohesion_energy_density = 0.5 * (a.cohesion_energy_density + b.cohesion_energy_density);
      if (const auto it = overrideOf.find(std::minmax(used[i], used[j])); it != overrideOf.end()) {
        const PairOverride& o = *it->second;
        p.restitution = o.restitution.value_or(p.restitution);
        p.sliding_friction = o.sliding_friction.value_or(p.sliding_friction);
        p.rolling_friction = o.rolling_friction.value_or(p.rolling_friction);
        p.cohesion_energy_density = o.cohesion_energy_density.value_or(p.cohesion_energy_density);
      }
      auto [it, inserted] = dampingOfRestitution.try_emplace(p.restitution, 0.0);
      if (inserted) it->second = law.damping_for_restitution(p.restitution);
      p.damping_coefficient = it->second;
      law.set_pair_coefficients(p, it->second, a, b, linearReference);
      // gamma_t = 2 zeta sqrt(S_t m*) = normal_damping sqrt(S_t / S_n) sqrt(S_n m*).
      p.tangential_damping = p.normal_damping * std::sqrt(tangentialStiffnessRatio(p));
      any_rolling_ = any_rolling_ || p.rolling_friction > 0.0;
      any_cohesion_ = any_cohesion_ || p.cohesion_energy_density > 0.0;
      pairs_[i * count_ + j] = p;
      pairs_[j * count_ + i] = p;
    }
  }
}

std::string_view toString(IntegratorKind integrator) {
  return integrator == IntegratorKind::VelocityVerlet ? "velocity_verlet" : "explicit_euler";
}

}  // namespace demlink::core
