#include "demlink/core/contact/contact_pair_table.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "demlink/core/input_error.hpp"
#include "demlink/core/contact/restitution_calibration.hpp"

namespace demlink::core {

double effectiveYoungsModulus(const Material& a, const Material& b) {
  return 1.0 / ((1.0 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                (1.0 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus);
}

double effectiveShearModulus(const Material& a, const Material& b) {
  return 1.0 / ((2.0 - a.poisson_ratio) / a.shearModulus() + (2.0 - b.poisson_ratio) / b.shearModulus());
}

void PairOverride::validate(const std::string& fieldPrefix) const {
  if (restitution) requireHalfOpenRange(fieldPrefix + ".restitution", *restitution, 0.0, 1.0);
  if (sliding_friction) requireNonNegative(fieldPrefix + ".sliding_friction", *sliding_friction);
  if (rolling_friction) requireNonNegative(fieldPrefix + ".rolling_friction", *rolling_friction);
}

namespace {

/// Linear k_n matching Hertz's maximum overlap for two reference spheres:
/// delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5), and k_n = m* v^2 / delta_max^2.
double matchedLinearStiffness(const Material& a, const Material& b, double eStar,
                              const LinearStiffnessReference& ref) {
  if (ref.normal_stiffness > 0.0) return ref.normal_stiffness;
  const double volume = 4.0 / 3.0 * std::numbers::pi * std::pow(ref.radius, 3);
  const double ma = a.density * volume;
  const double mb = b.density * volume;
  const double mStar = ma * mb / (ma + mb);
  const double rStar = 0.5 * ref.radius;
  const double v = ref.impact_velocity;
  const double deltaMax = std::pow(15.0 * mStar * v * v / (16.0 * eStar * std::sqrt(rStar)), 0.4);
  return mStar * v * v / (deltaMax * deltaMax);
}

}  // namespace

ContactPairTable::ContactPairTable(const std::vector<Material>& materials, ContactModel model,
                                   const LinearStiffnessReference& linearReference,
                                   const std::vector<PairOverrideEntry>& overrides)
    : count_(static_cast<std::uint32_t>(materials.size())), pairs_(materials.size() * materials.size()) {
  // Overrides by unordered pair (lower index first); scenes have few, a map is plenty.
  std::map<std::pair<std::uint32_t, std::uint32_t>, const PairOverride*> overrideOf;
  for (const PairOverrideEntry& entry : overrides) {
    overrideOf[std::minmax(entry.material_a, entry.material_b)] = &entry.values;
  }
  const NormalLaw law = model == ContactModel::HertzMindlin ? NormalLaw::Hertz : NormalLaw::Linear;
  std::map<double, double> dampingOfRestitution;  // calibration is ~ms each; reuse across pairs
  for (std::uint32_t i = 0; i < count_; ++i) {
    for (std::uint32_t j = i; j < count_; ++j) {
      const Material& a = materials[i];
      const Material& b = materials[j];
      ContactPairParams p;
      p.effective_youngs = effectiveYoungsModulus(a, b);
      p.effective_shear = effectiveShearModulus(a, b);
      // Different materials: arithmetic means, unless the scene overrides the pair.
      p.restitution = 0.5 * (a.restitution + b.restitution);
      p.sliding_friction = 0.5 * (a.sliding_friction + b.sliding_friction);
      p.rolling_friction = 0.5 * (a.rolling_friction + b.rolling_friction);
      if (const auto it = overrideOf.find({i, j}); it != overrideOf.end()) {
        const PairOverride& o = *it->second;
        p.restitution = o.restitution.value_or(p.restitution);
        p.sliding_friction = o.sliding_friction.value_or(p.sliding_friction);
        p.rolling_friction = o.rolling_friction.value_or(p.rolling_friction);
      }
      auto [it, inserted] = dampingOfRestitution.try_emplace(p.restitution, 0.0);
      if (inserted) it->second = dampingForRestitution(law, p.restitution);
      const double c = it->second;
      // Tangential/normal stiffness ratio 4 G*/E* (Mindlin; 2(1-nu)/(2-nu) for like materials).
      const double stiffnessRatio = 4.0 * p.effective_shear / p.effective_youngs;
      if (model == ContactModel::HertzMindlin) {
        // Paper eq. 6: gamma_n = 2 sqrt(5/6) |beta| sqrt(S_n m*). The dimensionless ODE
        // coefficient is c = sqrt(5) |beta|, hence 2 sqrt(5/6) |beta| = c sqrt(2/3).
        p.normal_damping = c * std::sqrt(2.0 / 3.0);
        p.beta = -c / std::sqrt(5.0);
      } else {
        // gamma_n = 2 zeta sqrt(k_n m*), with c = 2 zeta.
        p.normal_damping = c;
        p.beta = -0.5 * c;
        p.linear_normal_stiffness = matchedLinearStiffness(a, b, p.effective_youngs, linearReference);
        p.linear_tangential_stiffness = stiffnessRatio * p.linear_normal_stiffness;
      }
      p.tangential_damping = p.normal_damping * std::sqrt(stiffnessRatio);
      any_rolling_ = any_rolling_ || p.rolling_friction > 0.0;
      pairs_[i * count_ + j] = p;
      pairs_[j * count_ + i] = p;
    }
  }
}

std::string_view toString(ContactModel model) {
  return model == ContactModel::HertzMindlin ? "hertz_mindlin" : "linear_spring_dashpot";
}

std::string_view toString(IntegratorKind integrator) {
  return integrator == IntegratorKind::VelocityVerlet ? "velocity_verlet" : "explicit_euler";
}

}  // namespace demlink::core
