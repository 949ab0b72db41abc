#pragma once
/// The live view's caps as command-line options, the same on every program that serves the
/// view (demlink-server, demlink-run, demlink-view; docs/server.md, "Live view"). Each
/// writes into a ViewServerOptions whose defaults stand when the option is not given; a
/// value out of range exits 2 naming the option and the value. With `view` set (the
/// program's --view option) each needs it.
#include <cstddef>
#include <string>

#include "demlink/cli/command_line.hpp"
#include "demlink/server/view/view_server.hpp"

namespace demlink::server {

/// Most view connections one option may allow [-]: each holds a socket and a frame buffer.
inline constexpr std::size_t kMaxViewConnectionsCap = 1024;
/// Highest frame-rate cap [1/s]: each frame is a capture on the simulation's thread.
inline constexpr double kMaxViewFrameRateCap = 120.0;
/// Least byte budget per page [B/s]: the smallest frame (no particles) is 144 bytes.
inline constexpr double kMinViewBytesPerSecond = 1000.0;

inline void addViewCapOptions(CLI::App& app, ViewServerOptions& options, CLI::Option* view = nullptr) {
  CLI::Option* connections = cli::addWholeNumber<std::size_t>(app, "--view-max-connections", options.max_connections, 1, kMaxViewConnectionsCap,
                                   "view sockets open at once, pages and file requests together; one more gets "
                                   "HTTP 503 (default " + std::to_string(ViewServerOptions{}.max_connections) + ")");
  CLI::Option* rate = cli::addValue(app, "--view-max-rate",
                "highest frame rate a view page may ask for [frames/s], at most 120 (default 30)",
                [&options](const std::string& text) {
                  const double value = cli::number("--view-max-rate", text);
                  if (!(value > 0.0) || value > kMaxViewFrameRateCap) {
                    cli::refuse("--view-max-rate", text, "frames per second must be > 0 and <= 120");
                  }
                  options.max_frame_rate = value;
                })
      ->type_name("R");
  CLI::Option* bytes = cli::addNumber(app, "--view-max-bytes-per-second", options.max_bytes_per_second, {kMinViewBytesPerSecond, false},
                 "bytes per second sent to one view page; frames over it are skipped (default 64000000)")
      ->type_name("B");
  if (view != nullptr) {
    for (CLI::Option* cap : {connections, rate, bytes}) cap->needs(view);
  }
}

}  // namespace demlink::server
