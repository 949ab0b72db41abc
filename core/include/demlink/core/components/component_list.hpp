#pragma once
/// A world's scene components, and the two lists of those that run in stage
/// insert_remove and in stage observe (built as they are added, so a scene without
/// sources, sinks or sensors runs no component pass).
#include <memory>
#include <vector>

#include "demlink/core/components/world_component.hpp"

namespace demlink::core {

struct ComponentList {
  std::vector<std::unique_ptr<WorldComponent>> all;
  std::vector<WorldComponent*> insert_remove;
  std::vector<WorldComponent*> observe;
};

}  // namespace demlink::core
