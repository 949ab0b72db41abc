#pragma once
/// Appends a co-simulation session to a file (format: proto/demlink/v1/recording.proto,
/// docs/cosim.md "Recorder").
///
/// Why record inputs and not outputs: the world is deterministic for a given sequence of
/// messages, so the messages (plus markers for the two time-driven decisions) are enough
/// to re-create every output; the file stays small and a replay checks determinism.
#include <chrono>
#include <filesystem>
#include <fstream>

#include "demlink/server/cosim/cosim_host.hpp"
#include "demlink/v1/recording.pb.h"

namespace demlink::server {

class SessionRecorder {
 public:
  /// Creates (truncates) `path` and writes the HEADER event. Throws std::runtime_error if
  /// the file cannot be written.
  SessionRecorder(const std::filesystem::path& path, const CosimOptions& options);

  /// Appends one event (elapsed_s filled in) and flushes it.
  void record(v1::SessionEvent event);

 private:
  std::ofstream out_;
  std::filesystem::path path_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace demlink::server
