#pragma once
/// Mixes material properties into per-pair contact coefficients once, at set-up,
/// so the force stage only indexes a table (no mixing per contact). Only the materials
/// in use (by particles, future particles, planes, meshes and overrides) get rows: memory grows
/// with the square of the materials in use, not of the materials declared.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "demlink/core/contact/contact_model.hpp"
#include "demlink/core/materials/material.hpp"

namespace demlink::core {

/// Contact coefficients of one material pair given explicitly (scene component
/// material_pair) instead of the arithmetic mean of the two materials. Unset
/// values keep the mean. The damping is calibrated for the overriding e.
struct PairOverride {
  std::optional<double> restitution;       ///< e [-], in (0, 1]
  std::optional<double> sliding_friction;  ///< mu [-], >= 0
  std::optional<double> rolling_friction;  ///< mu_r [-], >= 0
  std::optional<double> cohesion_energy_density;  ///< k_c [J/m^3], >= 0

  /// Throws InputError naming `fieldPrefix + ".<field>"` for the first invalid value.
  void validate(const std::string& fieldPrefix) const;
};

/// An override for the unordered pair (material_a, material_b) (indices; equal
/// indices override a like-material pair).
struct PairOverrideEntry {
  std::uint32_t material_a = 0;
  std::uint32_t material_b = 0;
  PairOverride values;
};

class ContactPairTable {
 public:
  ContactPairTable() = default;
  /// The pairs among the materials `used` (indices into `materials`, each at most once).
  /// `overrides` must name existing materials, each unordered pair at most once
  /// (World::setPairOverride checks); all other pairs take the mean mix.
  ContactPairTable(const std::vector<Material>& materials, ContactModel model,
                   const LinearStiffnessReference& linearReference, const std::vector<PairOverrideEntry>& overrides,
                   const std::vector<std::uint32_t>& used);
  /// The pairs among all `materials`.
  ContactPairTable(const std::vector<Material>& materials, ContactModel model,
                   const LinearStiffnessReference& linearReference,
                   const std::vector<PairOverrideEntry>& overrides = {});

  /// The pair of materials a and b; both must be covered.
  [[nodiscard]] const ContactPairParams& operator()(std::uint32_t a, std::uint32_t b) const {
    return pairs_[std::size_t{slot_[a]} * count_ + slot_[b]];
  }
  /// Material m has a row.
  [[nodiscard]] bool covers(std::uint32_t m) const { return m < slot_.size() && slot_[m] != kNoSlot; }
  /// The covered materials, in row order.
  [[nodiscard]] const std::vector<std::uint32_t>& usedMaterials() const { return used_; }
  [[nodiscard]] bool anyRollingFriction() const { return any_rolling_; }
  /// Some covered pair has cohesion (k_c > 0): the force stage adds the cohesion pass.
  [[nodiscard]] bool anyCohesion() const { return any_cohesion_; }

 private:
  static constexpr std::uint32_t kNoSlot = 0xFFFFFFFFu;

  std::uint32_t count_ = 0;            ///< covered materials [-]
  std::vector<std::uint32_t> slot_;    ///< material index -> row (kNoSlot: not covered)
  std::vector<std::uint32_t> used_;    ///< row -> material index
  bool any_rolling_ = false;
  bool any_cohesion_ = false;
  std::vector<ContactPairParams> pairs_;
};

/// E* of two materials (solver paper eq. 3) [Pa].
double effectiveYoungsModulus(const Material& a, const Material& b);
/// G* of two materials [Pa]: (2(2-nu1)(1+nu1)/E1 + 2(2-nu2)(1+nu2)/E2)^-1.
/// The paper's eq. 4 prints (1-nu)/G; Mindlin's result is (2-nu)/G.
double effectiveShearModulus(const Material& a, const Material& b);

}  // namespace demlink::core
