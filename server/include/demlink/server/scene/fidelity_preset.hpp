#pragma once
/// Fidelity presets: SimulationBox.fidelity (DRAFT, ENGINEERING, VALIDATION) sets the
/// speed/accuracy knobs a box leaves unset, from what the atlas measured (demlink-study,
/// docs/accuracy.md): the contact law, the integrator, the restitution tolerance of the
/// time-step limit, and the largest share of that limit the time step should use. A field
/// the box gives explicitly always wins; the compile report prints every choice and where
/// it came from.
///
/// Why the preset does not set the time step itself: the limit is known only once the
/// world holds its particles (World::initialize), after the co-simulation compiler has
/// turned communication intervals into steps. The preset therefore checks the step and
/// warns, naming the step it recommends.
#include <string>
#include <vector>

#include "demlink/core/simulation_settings.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::core {
class World;
}

namespace demlink::server {

/// What one preset chooses.
struct FidelityKnobs {
  core::ContactModel contact_model = core::ContactModel::HertzMindlin;
  core::IntegratorKind integrator = core::IntegratorKind::VelocityVerlet;
  double restitution_tolerance = 0.1;  ///< of the time-step limit [-]
  double max_step_fraction = 1.0;      ///< largest time step / critical limit recommended [-]
};

/// The knobs of `preset`; throws InputError naming `field` for an unknown value or
/// FIDELITY_UNSPECIFIED.
[[nodiscard]] FidelityKnobs fidelityKnobs(v1::SimulationBox::Fidelity preset, const std::string& field);

/// What a box's preset chose, for the compile report.
struct FidelityChoice {
  std::string preset;                 ///< "DRAFT", ...; empty: no preset
  double max_step_fraction = 0.0;     ///< [-]; 0: no preset
  std::vector<std::string> lines;     ///< "<field> = <value> (preset|explicit)"
};

/// Applies the box's preset to `settings` (already translated from the box's explicit
/// fields): every knob the box leaves unset takes the preset's value. No preset: nothing
/// changes and the choice is empty.
[[nodiscard]] FidelityChoice applyFidelity(const v1::SimulationBox& box, const std::string& prefix,
                                           core::SimulationSettings& settings);

/// The compile report's lines for `choice` in an initialised `world`: the preset, its
/// choices, and a warning line ("warning: ...") when the time step is above the share of
/// the critical limit the preset recommends. Empty without a preset.
[[nodiscard]] std::vector<std::string> fidelityReportLines(const FidelityChoice& choice, const core::World& world);

}  // namespace demlink::server
