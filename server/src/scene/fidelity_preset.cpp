#include "demlink/server/scene/fidelity_preset.hpp"

#include <fmt/format.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/world.hpp"

namespace demlink::server {

FidelityKnobs fidelityKnobs(v1::SimulationBox::Fidelity preset, const std::string& field) {
  // From the atlas (docs/accuracy.md): the law and the integrator cost the same per step,
  // so every preset keeps Hertz-Mindlin and velocity Verlet (explicit Euler gains no speed
  // and loses energy); the presets differ in how close to the limit the step may go.
  FidelityKnobs knobs;
  switch (preset) {
    case v1::SimulationBox::DRAFT:
      knobs.restitution_tolerance = 0.1;
      knobs.max_step_fraction = 1.0;
      return knobs;
    case v1::SimulationBox::ENGINEERING:
      knobs.restitution_tolerance = 0.1;
      knobs.max_step_fraction = 0.5;
      return knobs;
    case v1::SimulationBox::VALIDATION:
      knobs.restitution_tolerance = 0.01;
      knobs.max_step_fraction = 1.0;
      return knobs;
    default:
      throw core::InputError(field, std::to_string(preset), "unknown fidelity (DRAFT, ENGINEERING or VALIDATION)");
  }
}

FidelityChoice applyFidelity(const v1::SimulationBox& box, const std::string& prefix,
                             core::SimulationSettings& settings) {
  FidelityChoice choice;
  if (box.fidelity() == v1::SimulationBox::FIDELITY_UNSPECIFIED) return choice;
  const FidelityKnobs knobs = fidelityKnobs(box.fidelity(), prefix + ".fidelity");
  choice.preset = v1::SimulationBox::Fidelity_Name(box.fidelity());
  choice.max_step_fraction = knobs.max_step_fraction;
  auto note = [&](const std::string& field, const std::string& value, bool isExplicit) {
    choice.lines.push_back(field + " = " + value + (isExplicit ? " (explicit)" : " (preset)"));
  };
  const bool lawGiven = box.contact_model() != v1::SimulationBox::CONTACT_MODEL_UNSPECIFIED;
  if (!lawGiven) settings.contact_model = knobs.contact_model;
  note("contact_model", std::string(core::toString(settings.contact_model)), lawGiven);
  const bool integratorGiven = box.integrator() != v1::SimulationBox::INTEGRATOR_UNSPECIFIED;
  if (!integratorGiven) settings.integrator = knobs.integrator;
  note("integrator", std::string(core::toString(settings.integrator)), integratorGiven);
  const bool toleranceGiven = box.has_restitution_tolerance();
  if (!toleranceGiven) settings.restitution_tolerance = knobs.restitution_tolerance;
  note("restitution_tolerance", core::formatValue(settings.restitution_tolerance), toleranceGiven);
  return choice;
}

std::vector<std::string> fidelityReportLines(const FidelityChoice& choice, const core::World& world) {
  std::vector<std::string> lines;
  if (choice.preset.empty()) return lines;
  lines.push_back("fidelity " + choice.preset + " (docs/accuracy.md):");
  for (const std::string& line : choice.lines) lines.push_back("  " + line);
  const double dt = world.settings().time_step;
  const double limit = world.timeStepReport().limit;
  const double recommended = choice.max_step_fraction * limit;
  lines.push_back(fmt::format("  time step <= {:.0f} % of the critical limit ({:.4g} s): {:.4g} s is {:.1f} %",
                              100.0 * choice.max_step_fraction, recommended, dt, 100.0 * dt / limit));
  if (dt > recommended * (1.0 + 1e-9)) {
    lines.push_back(fmt::format("warning: time_step {:.4g} s is above the {} preset's {:.0f} % of the critical limit; "
                                "use <= {:.4g} s",
                                dt, choice.preset, 100.0 * choice.max_step_fraction, recommended));
  }
  return lines;
}

}  // namespace demlink::server
