#pragma once
/// Scene builders shared by the server tests: a Scene from component JSON
/// snippets, and the field an invalid scene is rejected for.
#include <string>
#include <vector>

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"

namespace demlink::server::test {

/// Parses `{"components": [c0, c1, ...]}` from the given component objects.
inline v1::Scene sceneOf(const std::vector<std::string>& components) {
  std::string json = "{\"components\": [";
  for (std::size_t k = 0; k < components.size(); ++k) json += (k > 0 ? ", " : "") + components[k];
  return parseSceneJson(json + "]}", "test");
}

/// The field named by the InputError that translating and initialising throws,
/// or "(accepted)".
inline std::string errorFieldAfterInitialize(const v1::Scene& scene) {
  try {
    TranslatedScene t = translateScene(scene, {});
    t.world.initialize();
  } catch (const core::InputError& error) {
    return error.field();
  }
  return "(accepted)";
}

}  // namespace demlink::server::test
