/// The native backend and the backend names (contract in simulation_backend.hpp).
#include "demlink/server/backend/simulation_backend.hpp"

#include <algorithm>
#include <cctype>

#include "demlink/core/input_error.hpp"

namespace demlink::server {

BackendKind parseBackendKind(const std::string& field, const std::string& value) {
  std::string lower = value;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "native") return BackendKind::Native;
  if (lower == "liggghts") return BackendKind::Liggghts;
  throw core::InputError(field, value, "unknown backend; expected native or liggghts");
}

NativeBackend::NativeBackend(core::World& world) : world_(world) {
  if (!world_.initialized()) world_.initialize();
}

void NativeBackend::advanceTo(std::uint64_t step) {
  while (world_.stepCount() < step) world_.step();
}

}  // namespace demlink::server
