#include "demlink/core/contact/contact_law_registry.hpp"

#include <array>
#include <string>

#include "demlink/core/contact/restitution_calibration.hpp"
#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

template <class Law>
constexpr ContactLawEntry entryOf() {
  return {Law::kModel,
          Law::kName,
          &deliveredRestitution<Law>,
          &dampingForRestitution<Law>,
          &Law::setPairCoefficients,
          &Law::contactDuration,
          &step_calibration_detail::discreteRestitution<Law>,
          &step_calibration_detail::elasticDuration<Law>};
}

template <class... Laws>
constexpr std::array<ContactLawEntry, sizeof...(Laws)> tableOf(ContactLawList<Laws...>) {
  return {entryOf<Laws>()...};
}

constexpr auto kEntries = tableOf(ContactLaws{});

}  // namespace

std::span<const ContactLawEntry> contactLaws() { return kEntries; }

const ContactLawEntry& contactLaw(ContactModel model) {
  const auto index = static_cast<std::size_t>(model);
  if (index >= kEntries.size()) throw InputError("contact_model", std::to_string(index), "unknown contact law");
  return kEntries[index];
}

std::optional<ContactModel> contactModelNamed(std::string_view name) {
  for (const ContactLawEntry& entry : kEntries) {
    if (entry.name == name) return entry.model;
  }
  return std::nullopt;
}

std::string_view toString(ContactModel model) { return contactLaw(model).name; }

}  // namespace demlink::core
