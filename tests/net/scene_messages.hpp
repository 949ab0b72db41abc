// The client messages the server-process tests send: a scene's declarations and an
// empty DataPackage of one component at one step.
#pragma once

#include <cstdint>
#include <string>

#include "demlink/server/scene/scene_loader.hpp"
#include "test_client.hpp"

namespace demlink::server::test {

/// Sends each component of the scene `json` as a Declare; `what` names the scene in parse errors.
inline void declareAll(TestClient& client, const std::string& json,
                       const std::string& what = "server test scene") {
  const v1::Scene scene = parseSceneJson(json, what);
  for (const v1::ComponentDeclaration& component : scene.components()) {
    v1::ClientMessage declare;
    *declare.mutable_declare()->mutable_component() = component;
    client.send(declare);
  }
}

/// A DataPackage with no inputs for `component` at `step`.
inline v1::ClientMessage package(std::uint32_t component, std::uint64_t step) {
  v1::ClientMessage message;
  message.mutable_data()->set_component_id(component);
  message.mutable_data()->set_step(step);
  return message;
}

}  // namespace demlink::server::test
