/// Co-simulation lockstep across MPI ranks (contract in cosim_lockstep.hpp).
///
/// Wire: a batch is MPI_Bcast of its byte count (int64; -1: stop), then of its bytes:
/// events as (uint32 size, serialised v1::SessionEvent) one after another.
#include "demlink/server/cosim/cosim_lockstep.hpp"

#include <mpi.h>
#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "demlink/server/backend/liggghts_backend.hpp"
#include "demlink/server/cosim/session_replay.hpp"

namespace demlink::server {
namespace {

constexpr std::int64_t kStop = -1;

void broadcastSize(std::int64_t& size) { MPI_Bcast(&size, 1, MPI_INT64_T, 0, MPI_COMM_WORLD); }

/// Rank 0's wish to stop, taken by every rank (CosimOptions::stop_consensus). One int per
/// step: LIGGGHTS's own step makes several collectives of that size.
bool broadcastStop(bool stop) {
  int flag = stop ? 1 : 0;
  MPI_Bcast(&flag, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return flag != 0;
}

}  // namespace

LockstepLeader::~LockstepLeader() {
  try {
    close();
  } catch (const std::exception& error) {
    spdlog::error("stopping the MPI mirrors failed: {}", error.what());
  }
}

void LockstepLeader::attach(CosimOptions& options) {
  options.on_event = [this](const v1::SessionEvent& event) { add(event); };
  options.before_engine = [this] { flush(); };
  options.stop_consensus = broadcastStop;
}

void LockstepLeader::add(const v1::SessionEvent& event) {
  const std::string bytes = event.SerializeAsString();
  const auto size = static_cast<std::uint32_t>(bytes.size());
  char prefix[sizeof size];
  std::memcpy(prefix, &size, sizeof size);
  batch_.append(prefix, sizeof size);
  batch_ += bytes;
}

void LockstepLeader::flush() {
  if (batch_.empty() || closed_) return;
  std::int64_t size = static_cast<std::int64_t>(batch_.size());
  broadcastSize(size);
  MPI_Bcast(batch_.data(), static_cast<int>(batch_.size()), MPI_CHAR, 0, MPI_COMM_WORLD);
  batch_.clear();
}

void LockstepLeader::close() {
  if (closed_) return;
  flush();
  std::int64_t stop = kStop;
  broadcastSize(stop);
  closed_ = true;
}

void runLockstepMirror(CosimOptions options) {
  const int rank = ensureMpi();
  const std::filesystem::path scratch =
      std::filesystem::temp_directory_path() / fmt::format("demlink-mirror-{}-{}", rank, static_cast<long>(::getpid()));
  options.mirror = true;
  options.output_root = scratch;
  options.overwrite = true;
  options.record_file.clear();
  options.on_event = nullptr;
  options.before_engine = nullptr;
  // Rank 0 decides when an interval is cut short (its server's shutdown); a signal here
  // is rank 0's too (mpirun forwards SIGTERM to every rank), which tells this rank.
  options.stop_stepping = nullptr;
  options.stop_consensus = [](bool) { return broadcastStop(false); };
  std::signal(SIGINT, SIG_IGN);
  std::signal(SIGTERM, SIG_IGN);
  options.progress_interval_s = 0.0;
  std::uint64_t batches = 0;
  {
    CosimHost host(options);
    for (;;) {
      std::int64_t size = 0;
      broadcastSize(size);
      if (size == kStop) break;
      std::string batch(static_cast<std::size_t>(size), '\0');
      MPI_Bcast(batch.data(), static_cast<int>(size), MPI_CHAR, 0, MPI_COMM_WORLD);
      ++batches;
      for (std::size_t at = 0; at < batch.size();) {
        std::uint32_t length = 0;
        std::memcpy(&length, batch.data() + at, sizeof length);
        at += sizeof length;
        v1::SessionEvent event;
        if (!event.ParseFromArray(batch.data() + at, static_cast<int>(length))) {
          throw std::runtime_error(fmt::format("MPI rank {}: a bad event from rank 0", rank));
        }
        at += length;
        (void)replayEvent(host, event, SteadyClock::now());  // the answers are rank 0's to send
      }
    }
  }
  std::error_code ignored;
  std::filesystem::remove_all(scratch, ignored);
  spdlog::debug("MPI rank {}: mirror stopped after {} batches", rank, batches);
}

}  // namespace demlink::server
