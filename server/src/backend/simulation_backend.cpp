/// The native backend and the backend names (contract in simulation_backend.hpp).
#include "demlink/server/backend/simulation_backend.hpp"

#include <algorithm>
#include <cctype>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/checkpoint_file.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {

BackendKind parseBackendKind(const std::string& field, const std::string& value) {
  std::string lower = value;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "native") return BackendKind::Native;
  if (lower == "liggghts") return BackendKind::Liggghts;
  throw core::InputError(field, value, "unknown backend; expected native or liggghts");
}

void requireBackendAgrees(const v1::Scene& scene, BackendKind backend) {
  for (int i = 0; i < scene.components_size(); ++i) {
    const v1::ComponentDeclaration& component = scene.components(i);
    if (!component.has_simulation_box()) continue;
    const v1::SimulationBox::Backend wanted = component.simulation_box().backend();
    if (wanted == v1::SimulationBox::BACKEND_UNSPECIFIED) continue;
    if ((wanted == v1::SimulationBox::LIGGGHTS) != (backend == BackendKind::Liggghts)) {
      throw core::InputError(componentPath(i) + ".simulation_box.backend", v1::SimulationBox::Backend_Name(wanted),
                             std::string("the scene and the command line (--backend ") +
                                 (backend == BackendKind::Liggghts ? "liggghts" : "native") + ") must agree");
    }
  }
}

NativeBackend::NativeBackend(core::World& world) : world_(world) {
  if (!world_.initialized()) world_.initialize();
}

void NativeBackend::advanceTo(std::uint64_t step) {
  if (world_.stepCount() < step) world_.advance(step - world_.stepCount());
}

void NativeBackend::writeCheckpoint(const std::filesystem::path& base) { core::writeCheckpointFile(world_, base); }

}  // namespace demlink::server
