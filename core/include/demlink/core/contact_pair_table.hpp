#pragma once
/// Mixes material properties into per-pair contact coefficients once, at set-up,
/// so the force stage only indexes a table (no mixing per contact).
#include <cstdint>
#include <vector>

#include "demlink/core/contact_model.hpp"
#include "demlink/core/material.hpp"

namespace demlink::core {

/// Reference scales for the linear law's stiffness when the scene gives none:
/// k_n is chosen so a head-on impact of two reference spheres at the reference
/// speed reaches the same maximum overlap as under Hertz.
struct LinearStiffnessReference {
  double radius = 0.0;          ///< [m] reference particle radius (scene mean)
  double impact_velocity = 1.0; ///< [m/s]
  double normal_stiffness = 0.0;///< [N/m] if > 0, used as given for every pair
};

class ContactPairTable {
 public:
  ContactPairTable() = default;
  ContactPairTable(const std::vector<Material>& materials, ContactModel model,
                   const LinearStiffnessReference& linearReference);

  [[nodiscard]] const ContactPairParams& operator()(std::uint32_t a, std::uint32_t b) const {
    return pairs_[a * count_ + b];
  }
  [[nodiscard]] std::uint32_t materialCount() const { return count_; }
  [[nodiscard]] bool anyRollingFriction() const { return any_rolling_; }

 private:
  std::uint32_t count_ = 0;
  bool any_rolling_ = false;
  std::vector<ContactPairParams> pairs_;
};

/// E* of two materials (solver paper eq. 3) [Pa].
double effectiveYoungsModulus(const Material& a, const Material& b);
/// G* of two materials [Pa]: (2(2-nu1)(1+nu1)/E1 + 2(2-nu2)(1+nu2)/E2)^-1.
/// The paper's eq. 4 prints (1-nu)/G; Mindlin's result is (2-nu)/G.
double effectiveShearModulus(const Material& a, const Material& b);

}  // namespace demlink::core
