#pragma once
/// The contact-law registry. One line (ContactLaws) lists the compile-time law
/// types in ContactModel order; from it come the run-time table — each law's
/// name, restitution calibration, pair coefficients and contact duration — and
/// visitContactLaw, through which World picks its force-stage instantiation
/// once at initialisation (the force loop itself never branches on the law).
///
/// Adding a law: its own file (like hertz_mindlin_law.hpp) with a type that
/// satisfies ContactLawType, its ContactModel value, and one entry in ContactLaws.
#include <concepts>
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <type_traits>

#include "demlink/core/contact/contact_model.hpp"
#include "demlink/core/contact/hertz_mindlin_law.hpp"
#include "demlink/core/contact/linear_spring_dashpot_law.hpp"
#include "demlink/core/contact/time_step_calibration.hpp"
#include "demlink/core/materials/material.hpp"

namespace demlink::core {

/// What a contact law type provides.
template <class Law>
concept ContactLawType = requires(ContactPairParams& p, const Material& m, const LinearStiffnessReference& ref,
                                  double x) {
  { Law::kModel } -> std::convertible_to<ContactModel>;
  { Law::kName } -> std::convertible_to<std::string_view>;
  typename Law::History;  // per-contact history the near lists keep for it
  { Law::stiffness(p, x, x) } -> std::same_as<ContactStiffness>;          // (p, rStar, overlap), per contact
  { Law::dimensionlessAcceleration(x, x, x) } -> std::same_as<double>;    // (x, v, c), restitution ODE
  { Law::setPairCoefficients(p, x, m, m, ref) } -> std::same_as<void>;   // (p, c, a, b, reference)
  { Law::contactDuration(p, x, x, x) } -> std::same_as<double>;           // (p, rStar, mStar, speed) [s]
};

template <ContactLawType... Laws>
struct ContactLawList {};

/// Every contact law, in ContactModel order.
using ContactLaws = ContactLawList<HertzMindlinLaw, LinearSpringDashpotLaw>;

/// One row of the run-time table: what set-up and reports need of a law.
struct ContactLawEntry {
  ContactModel model;
  std::string_view name;  ///< in reports and run logs, e.g. "hertz_mindlin"
  /// Rebound ratio delivered by the dimensionless damping coefficient c.
  double (*delivered_restitution)(double c);
  /// The dimensionless damping coefficient c delivering restitution e in (0, 1].
  double (*damping_for_restitution)(double e);
  /// Fills the law's damping and stiffness of a pair whose moduli and e are set.
  void (*set_pair_coefficients)(ContactPairParams& p, double c, const Material& a, const Material& b,
                                const LinearStiffnessReference& linearReference);
  /// Duration [s] of a head-on impact at impactSpeed [m/s].
  double (*contact_duration)(const ContactPairParams& p, double rStar, double mStar, double impactSpeed);
  /// Rebound ratio the engine's integrator delivers for damping c at the
  /// dimensionless step h and onset phase in [0, 1) (time_step_calibration.hpp).
  double (*discrete_restitution)(double c, double h, double phase, IntegratorKind integrator);
  /// Dimensionless duration of the undamped contact (its ODE's time unit).
  double (*elastic_duration)();
};

/// All entries, indexed by ContactModel value.
std::span<const ContactLawEntry> contactLaws();
/// The entry of `model`; throws InputError for a value outside the enum.
const ContactLawEntry& contactLaw(ContactModel model);
/// The law called `name` (ContactLawEntry::name), if any.
std::optional<ContactModel> contactModelNamed(std::string_view name);

namespace contact_law_detail {

template <class... Laws>
consteval bool listedInEnumOrder(ContactLawList<Laws...>) {
  std::size_t index = 0;
  return ((static_cast<std::size_t>(Laws::kModel) == index++) && ...) && sizeof...(Laws) == kContactModelCount;
}

template <class Visitor, class Law, class... Rest>
decltype(auto) visit(ContactModel model, Visitor& visitor, ContactLawList<Law, Rest...>) {
  if constexpr (sizeof...(Rest) == 0) {
    return visitor.template operator()<Law>();  // contactLaw(model) has checked the range
  } else {
    if (model == Law::kModel) return visitor.template operator()<Law>();
    return visit(model, visitor, ContactLawList<Rest...>{});
  }
}

}  // namespace contact_law_detail

static_assert(contact_law_detail::listedInEnumOrder(ContactLaws{}),
              "ContactLaws lists every ContactModel value once, in enum order");

/// Calls `visitor.template operator()<Law>()` with the law type of `model` and
/// returns its result (the same type for every law). Meant for set-up: World
/// takes the address of its force stage instantiated for Law here.
template <class Visitor>
decltype(auto) visitContactLaw(ContactModel model, Visitor&& visitor) {
  (void)contactLaw(model);
  return contact_law_detail::visit(model, visitor, ContactLaws{});
}

}  // namespace demlink::core
