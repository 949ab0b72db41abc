#pragma once
/// Re-runs a recorded co-simulation session (session_recorder.hpp) from the file alone: no
/// network, no clients. `demlink-server --replay FILE` calls it.
///
/// The replay feeds every recorded event into a fresh CosimHost in order; the
/// time-driven markers call CosimHost::compileNow() / expireWaitNow() instead of
/// waiting for a clock, so the replayed world takes exactly the live run's steps.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "demlink/server/cosim/cosim_host.hpp"
#include "demlink/v1/recording.pb.h"

namespace demlink::server {

struct ReplayResult {
  std::vector<v1::Finished> finished;  ///< every Finished the host sent, in order (one per connection)
  std::vector<v1::Error> errors;       ///< every Error the host sent, in order
  std::filesystem::path output_directory;  ///< of the last simulation that ran (empty: none)
  std::uint64_t simulations = 0;       ///< simulations that ended [-]
  std::uint64_t events = 0;            ///< events replayed (header excluded) [-]
};

/// Feeds one recorded event (not the HEADER) into `host` at `now`, as the live host took
/// it; returns what the host answered, or nullopt for an event of unknown kind.
[[nodiscard]] std::optional<std::vector<Outgoing>> replayEvent(CosimHost& host, const v1::SessionEvent& event,
                                                               SteadyClock::time_point now);

/// Replays `file`. The recorded scene file and scene directory replace those in `options`;
/// output_root, quiet period and timeout are taken from `options` (the timers do not run);
/// record_file is ignored. Throws std::runtime_error for a file that cannot be read, a bad
/// frame or an event of unknown kind (naming the event's index).
[[nodiscard]] ReplayResult replaySession(const std::filesystem::path& file, CosimOptions options);

}  // namespace demlink::server
