#pragma once
/// What the contact output records (contact_record.hpp) and keeps: the settings a
/// run asked for, the contacts of the last recorded force evaluation, the loads per
/// mesh triangle with their time integrals, and the force stage's per-chunk record
/// buffers (merged in chunk order, so the records do not depend on the thread count).
/// Inactive settings (the default) leave the recording pass out of the force stage.
#include <vector>

#include "demlink/core/contact/contact_record.hpp"

namespace demlink::core {

struct ContactRecorder {
  ContactOutputSettings settings;
  ContactSnapshot snapshot;  ///< contacts of the last recorded force evaluation
  std::vector<std::vector<TriangleLoad>> mesh_loads;     ///< per mesh, per triangle (mesh loads on)
  std::vector<std::vector<ContactRecord>> part_records;  ///< per pair-loop chunk, merged in chunk order
};

}  // namespace demlink::core
