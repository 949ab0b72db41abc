#include "demlink/core/contact/critical_time_step.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <spdlog/fmt/fmt.h>

#include "demlink/core/contact/contact_law_registry.hpp"
#include "demlink/core/contact/time_step_calibration.hpp"
#include "demlink/core/particles/sphere.hpp"

namespace demlink::core {

double rayleighTimeStep(const Material& m, double radius) {
  return std::numbers::pi * radius * std::sqrt(m.density / m.shearModulus()) / (0.1631 * m.poisson_ratio + 0.8766);
}

void TimeStepReport::addConstraint(TimeStepConstraint constraint) {
  if (constraints.empty() || constraint.limit < limit) {
    limit = constraint.limit;
    limited_by = constraint.name;
  }
  constraints.push_back(std::move(constraint));
}

namespace {

/// A limit in a report: +inf (nothing limits the step) is said in words, never "inf".
std::string limitText(double seconds) {
  return std::isfinite(seconds) ? fmt::format("{:.6g} s", seconds) : std::string("no limit");
}

}  // namespace

std::vector<std::string> TimeStepReport::describe() const {
  std::vector<std::string> lines;
  lines.push_back(fmt::format("critical time step {}, limited by {}", limitText(limit), limited_by));
  for (const TimeStepConstraint& c : constraints) {
    lines.push_back(fmt::format("  {}: {} ({})", c.name, limitText(c.limit), c.detail));
  }
  for (const PairDampingReport& d : damping) {
    lines.push_back(fmt::format("  damping {}/{}: e = {:.6g}, c = {:.6g}, beta = {:.6g}, gamma_n / sqrt(S_n m*) = "
                                "{:.6g}, gamma_t / sqrt(S_n m*) = {:.6g}, dt <= {:.4g} t_c",
                                d.material_a, d.material_b, d.restitution, d.damping_coefficient, d.beta,
                                d.normal_damping, d.tangential_damping, d.step_fraction));
  }
  return lines;
}

TimeStepReport criticalTimeStep(const std::vector<Material>& materials, const ContactPairTable& table,
                                ContactModel model, IntegratorKind integrator,
                                const std::vector<double>& minRadiusOfMaterial, double impactSpeed,
                                double restitutionTolerance) {
  const ContactLawEntry& law = contactLaw(model);
  TimeStepReport report;
  report.impact_speed = impactSpeed;
  report.restitution_tolerance = restitutionTolerance;
  report.rayleigh_time_step = std::numeric_limits<double>::infinity();
  report.contact_duration = std::numeric_limits<double>::infinity();
  auto massOf = [&](std::size_t k) { return sphereMass(minRadiusOfMaterial[k], materials[k].density); };
  std::size_t rayleighMaterial = 0;
  TimeStepConstraint contact{"", "", std::numeric_limits<double>::infinity()};
  for (std::size_t a = 0; a < materials.size(); ++a) {
    if (minRadiusOfMaterial[a] <= 0.0 || !table.covers(static_cast<std::uint32_t>(a))) continue;
    const double tr = rayleighTimeStep(materials[a], minRadiusOfMaterial[a]);
    if (tr < report.rayleigh_time_step) {
      report.rayleigh_time_step = tr;
      rayleighMaterial = a;
    }
    for (const std::uint32_t b : table.usedMaterials()) {
      // Each particle pair once (a <= b); wall materials against every particle material.
      const bool particlePair = minRadiusOfMaterial[b] > 0.0;
      if (particlePair && b < a) continue;
      const ContactPairParams& p = table(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b));
      const double ra = minRadiusOfMaterial[a];
      const double ma = massOf(a);
      double rStar = ra;  // against a wall of material b
      double mStar = ma;
      if (particlePair) {
        const double rb = minRadiusOfMaterial[b];
        const double mb = massOf(b);
        rStar = ra * rb / (ra + rb);
        mStar = ma * mb / (ma + mb);
      }
      const double duration = law.contact_duration(p, rStar, mStar, impactSpeed);
      report.contact_duration = std::min(report.contact_duration, duration);
      const double fraction =
          accurateStepFraction(model, integrator, p.restitution, p.damping_coefficient, restitutionTolerance);
      report.damping.push_back({materials[a].name, materials[b].name, p.restitution, p.damping_coefficient, p.beta,
                                p.normal_damping, p.tangential_damping, fraction, particlePair});
      if (fraction * duration < contact.limit) {
        contact.limit = fraction * duration;
        contact.name = fmt::format("restitution {}/{} (e = {:.6g})", materials[a].name, materials[b].name,
                                   p.restitution);
        contact.detail = fmt::format("{:.4g} x contact duration {:.6g} s at {:.6g} m/s ({} {}); error <= {:.3g} of e "
                                     "over every onset phase with {}",
                                     fraction, duration, impactSpeed, particlePair ? "particle pair" : "on a wall",
                                     law.name, restitutionTolerance, toString(integrator));
      }
    }
  }
  if (std::isfinite(report.rayleigh_time_step)) {
    report.addConstraint({"rayleigh",
                          fmt::format("{} x Rayleigh time {:.6g} s of the smallest {} particle", kRayleighSafetyFraction,
                                      report.rayleigh_time_step, materials[rayleighMaterial].name),
                          kRayleighSafetyFraction * report.rayleigh_time_step});
  }
  if (std::isfinite(contact.limit)) report.addConstraint(std::move(contact));
  if (report.constraints.empty()) {
    report.addConstraint({"none", "no particles declared", std::numeric_limits<double>::infinity()});
  }
  return report;
}

}  // namespace demlink::core
