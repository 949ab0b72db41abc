#pragma once
/// What a page may ask of the view over its WebSocket: "rate=10 max=100000 colour=speed
/// frame=3 sim=2" (any subset, separated by spaces or ';'). Parsed here, apart from the sockets,
/// so that tests check every refusal.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "demlink/server/view/view_snapshot.hpp"

namespace demlink::server {

/// Most particles one page may ask for per frame [-].
inline constexpr std::size_t kMaxViewParticles = 10'000'000;

struct ViewRequest {
  std::optional<double> rate;  ///< frames per second
  std::optional<std::size_t> max_particles;
  std::optional<ColourField> colour;
  std::optional<std::uint32_t> frame;  ///< recorded runs
  std::optional<std::uint64_t> simulation;  ///< the id of the simulation to follow (live servers)
};

/// Parses one request; on a bad item returns nullopt and sets `error` to
/// "<name> = <value>: <reason>". `maxRate` bounds rate.
[[nodiscard]] std::optional<ViewRequest> parseViewRequest(std::string_view text, double maxRate, std::string& error);

/// "speed", "force", "material", "id".
[[nodiscard]] std::string_view colourFieldName(ColourField field);

}  // namespace demlink::server
