/// Session replay (contract in session_replay.hpp).
#include "demlink/server/cosim/session_replay.hpp"

#include <spdlog/spdlog.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/input_file.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/v1/recording.pb.h"
#include "demlink/wire/frame_codec.hpp"

namespace demlink::server {
namespace {

/// A record that does not read as one is bad input (the tool exits 2), not a failure.
core::InputError corrupt(const std::filesystem::path& file, const std::string& reason) {
  return core::InputError("session record", core::logText(file.string()), reason);
}

}  // namespace

std::optional<std::vector<Outgoing>> replayEvent(CosimHost& host, const v1::SessionEvent& event,
                                                 SteadyClock::time_point now) {
  switch (event.kind()) {
    case v1::SessionEvent::CONNECTED: return host.connected(event.connection(), event.message().hello(), now);
    case v1::SessionEvent::RECEIVED: return host.received(event.connection(), event.message(), now);
    case v1::SessionEvent::DISCONNECTED: return host.disconnected(event.connection(), event.text(), now);
    case v1::SessionEvent::COMPILE_NOW: return host.compileNow(now);
    case v1::SessionEvent::TIMEOUT: return host.expireWaitNow(now);
    case v1::SessionEvent::ASSEMBLY_TIMEOUT: return host.expireAssemblyNow(now);
    case v1::SessionEvent::SHUTDOWN: return host.shutdown(event.text(), now);
    default: return std::nullopt;
  }
}

ReplayResult replaySession(const std::filesystem::path& file, CosimOptions options) {
  wire::FrameDecoder decoder(std::numeric_limits<std::size_t>::max() / 2);
  decoder.feed(core::readInputFile("session record", file));

  options.record_file.clear();
  std::unique_ptr<CosimHost> host;
  ReplayResult result;
  const SteadyClock::time_point origin{};
  std::uint64_t index = 0;
  const auto collect = [&](const std::vector<Outgoing>& messages) {
    for (const Outgoing& m : messages) {
      if (m.message.has_finished()) {
        result.finished.push_back(m.message.finished());
        if (!m.message.finished().output_directory().empty()) {
          result.output_directory = m.message.finished().output_directory();
        }
      }
      if (m.message.has_error()) result.errors.push_back(m.message.error());
    }
  };
  while (std::optional<std::string> payload = decoder.next()) {
    v1::SessionEvent event;
    if (!wire::parsePayload(*payload, event)) {
      throw corrupt(file, "event " + std::to_string(index) + " is not a SessionEvent");
    }
    const auto now = origin + std::chrono::duration_cast<SteadyClock::duration>(
                                  std::chrono::duration<double>(event.elapsed_s()));
    if (index == 0) {
      if (event.kind() != v1::SessionEvent::HEADER) {
        throw corrupt(file, "the first event is not a HEADER");
      }
      options.base_scene = event.base_scene();
      options.scene_directory = event.scene_directory();
      if (!event.data_root().empty()) options.data_root = event.data_root();
      host = std::make_unique<CosimHost>(options);
      ++index;
      continue;
    }
    const std::optional<std::vector<Outgoing>> answers = replayEvent(*host, event, now);
    if (!answers) {
      throw corrupt(file, "event " + std::to_string(index) + " has unknown kind " +
                               std::to_string(static_cast<int>(event.kind())));
    }
    collect(*answers);
    ++index;
    ++result.events;
  }
  if (decoder.error() != wire::FrameError::None || decoder.pendingBytes() > 0) {
    throw corrupt(file, "bad or truncated frame after event " + std::to_string(index) +
                             (decoder.errorMessage().empty() ? "" : ": " + decoder.errorMessage()));
  }
  if (!host) throw corrupt(file, "empty session record");
  result.simulations = host->simulationsFinished();
  spdlog::info("replayed {} events of {}: {} simulations", result.events, file.string(), result.simulations);
  return result;
}

}  // namespace demlink::server
