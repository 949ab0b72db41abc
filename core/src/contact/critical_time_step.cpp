#include "demlink/core/contact/critical_time_step.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "demlink/core/contact/contact_law_registry.hpp"

namespace demlink::core {

double rayleighTimeStep(const Material& m, double radius) {
  return std::numbers::pi * radius * std::sqrt(m.density / m.shearModulus()) / (0.1631 * m.poisson_ratio + 0.8766);
}

TimeStepReport criticalTimeStep(const std::vector<Material>& materials, const ContactPairTable& table,
                                ContactModel model, const std::vector<double>& minRadiusOfMaterial,
                                double maxImpactVelocity) {
  const ContactLawEntry& law = contactLaw(model);
  TimeStepReport report;
  report.rayleigh_time_step = std::numeric_limits<double>::infinity();
  report.contact_duration = std::numeric_limits<double>::infinity();
  auto massOf = [&](std::size_t k) {
    const double r = minRadiusOfMaterial[k];
    return 4.0 / 3.0 * std::numbers::pi * r * r * r * materials[k].density;
  };
  for (std::size_t a = 0; a < materials.size(); ++a) {
    if (minRadiusOfMaterial[a] <= 0.0 || !table.covers(static_cast<std::uint32_t>(a))) continue;
    report.rayleigh_time_step = std::min(report.rayleigh_time_step, rayleighTimeStep(materials[a], minRadiusOfMaterial[a]));
    for (const std::uint32_t b : table.usedMaterials()) {
      const ContactPairParams& p = table(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b));
      const double ra = minRadiusOfMaterial[a];
      const double ma = massOf(a);
      double rStar = ra;  // against a rigid wall of material b
      double mStar = ma;
      if (minRadiusOfMaterial[b] > 0.0) {
        const double rb = minRadiusOfMaterial[b];
        const double mb = massOf(b);
        rStar = ra * rb / (ra + rb);
        mStar = ma * mb / (ma + mb);
      }
      report.contact_duration = std::min(report.contact_duration, law.contact_duration(p, rStar, mStar, maxImpactVelocity));
    }
  }
  const double byRayleigh = kRayleighSafetyFraction * report.rayleigh_time_step;
  const double byContact = report.contact_duration / kMinStepsPerContact;
  report.limit = std::min(byRayleigh, byContact);
  report.limited_by = byRayleigh <= byContact ? "rayleigh" : "contact duration";
  return report;
}

}  // namespace demlink::core
