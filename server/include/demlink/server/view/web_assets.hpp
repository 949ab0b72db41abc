#pragma once
/// The view's page (server/web/), built into the program by cmake/DemlinkEmbedFiles.cmake.
#include <span>
#include <string_view>

namespace demlink::server {

struct WebAsset {
  std::string_view name;   ///< file name under server/web/, e.g. "view.js"
  std::string_view bytes;
};

[[nodiscard]] std::span<const WebAsset> webAssets();

}  // namespace demlink::server
