#pragma once
/// Several co-simulations at once behind one network loop (docs/server.md, "Several
/// simulations" and "Threads").
///
/// The hub is what the transport drives. It never steps a world: each simulation has its
/// own CosimHost on its own thread (SimulationWorker), and the hub only routes. A Hello
/// joins the simulation being assembled under the same Hello.simulation, or opens a new
/// one while fewer than `max_open` are open; every later message of that connection goes
/// to its simulation's thread, and what the host answers comes back through the
/// transport's LoopPoster. So a connection is answered at once whatever any simulation is
/// doing, and one simulation's fault, stall or size never delays another's answers. The
/// simulations that step at the same time share the CPUs by SteppingTurns.
///
/// Thread use: connected / received / disconnected / shutdown run on the network thread;
/// the hub's routing state is that thread's alone. Each slot's status is published by its
/// worker through the posted reports, so it is read on the network thread too.
#include <atomic>
#include <functional>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "demlink/core/parallel/spin_wait.hpp"
#include "demlink/server/cosim/cosim_host.hpp"
#include "demlink/server/net/session_handler.hpp"

namespace demlink::server {

class SessionRecorder;
class SimulationWorker;
class SteppingTurns;

struct SimulationHubOptions {
  /// Simulations pending or running at once; a Hello that would open one more is refused
  /// with SERVER_BUSY naming who holds them. With a session record: 1 (a record is one
  /// host's sequence of events).
  std::size_t max_open = 8;
  /// Simulations stepping at once (SteppingTurns) [-].
  std::size_t max_stepping = 1;
  /// A stepping simulation gives its turn to a waiting one after this much stepping.
  std::chrono::milliseconds stepping_slice{50};
  /// Simulations opened in all, 0: no limit (demlink-server --max-simulations: the server
  /// exits once that many have ended, so it opens no more).
  std::uint64_t max_total = 0;
  /// Spin budget of each simulation thread's wait for its next call (SimulationWorker;
  /// demlink-server passes its --spin-wait-us, the network loop's); zero: block at once.
  std::chrono::nanoseconds spin_wait = core::defaultSpinBudget();
};

class SimulationHub final : public SessionHandler {
 public:
  /// `host` is the template of every simulation's host options (its restore_file goes to
  /// the first simulation only; its record_file is written by the hub, for all).
  SimulationHub(CosimOptions host, SimulationHubOptions options);
  ~SimulationHub() override;
  SimulationHub(const SimulationHub&) = delete;
  SimulationHub& operator=(const SimulationHub&) = delete;

  void attachLoop(LoopPoster poster) override;
  std::vector<Outgoing> connected(ConnectionId id, const v1::Hello& hello, SteadyClock::time_point now) override;
  std::vector<Outgoing> received(ConnectionId from, const v1::ClientMessage& message,
                                 SteadyClock::time_point now) override;
  std::vector<Outgoing> disconnected(ConnectionId id, const std::string& why, SteadyClock::time_point now) override;
  /// Messages of `id` posted to its simulation's thread and not reported yet.
  [[nodiscard]] std::size_t pendingCalls(ConnectionId id) const override;
  /// The hub has no timers of its own: each simulation's thread runs its host's.
  std::vector<Outgoing> poll(SteadyClock::time_point /*now*/) override { return {}; }
  [[nodiscard]] std::optional<SteadyClock::time_point> nextDeadline() const override { return std::nullopt; }
  /// Stops every simulation at its next step boundary, lets each host end it (outputs,
  /// final checkpoint, SERVER_SHUTDOWN to its clients) and returns those messages once
  /// every simulation thread has ended.
  std::vector<Outgoing> shutdown(const std::string& reason, SteadyClock::time_point now) override;

  /// Simulations ended so far (thread-safe) [-].
  [[nodiscard]] std::uint64_t simulationsFinished() const { return finished_.load(); }
  /// Simulations open now (pending or running; network thread) [-].
  [[nodiscard]] std::size_t openSimulations() const { return slots_.size(); }

 private:
  struct Slot;

  /// A slot for `hello`'s group: the one assembling it, an idle one, or a new one; null
  /// with the refusal in `refusal` otherwise.
  Slot* route(const v1::Hello& hello, SteadyClock::time_point now, std::optional<v1::Error>& refusal);
  Slot& open();
  /// Posts a call for connection `id` to `slot`'s thread, counted until it is reported.
  void post(Slot& slot, ConnectionId id, std::function<std::vector<Outgoing>(CosimHost&)> call);
  /// Calls of `slot` up to `callsDone` have run (all of them: `callsDone` = max).
  void settle(Slot& slot, std::uint64_t callsDone);
  /// The transport's thread, with a worker's report.
  std::vector<Outgoing> onReport(std::uint64_t number, std::vector<Outgoing> out, CosimHost::Status status,
                                 bool ended, std::uint64_t calls_done);
  /// Who holds the open simulations, for a refused client.
  [[nodiscard]] std::string holders(SteadyClock::time_point now) const;

  CosimOptions host_options_;
  SimulationHubOptions options_;
  std::shared_ptr<SteppingTurns> turns_;
  std::unique_ptr<SessionRecorder> recorder_;
  std::mutex recorder_mutex_;
  mutable std::mutex post_mutex_;
  LoopPoster post_;
  std::map<std::uint64_t, std::unique_ptr<Slot>> slots_;  ///< by simulation number
  std::unordered_map<ConnectionId, std::uint64_t> members_;  ///< connection -> its simulation
  std::unordered_map<ConnectionId, std::size_t> pending_calls_;  ///< posted, not reported yet
  std::uint64_t next_number_ = 1;
  std::uint64_t opened_ = 0;
  std::atomic<std::uint64_t> finished_{0};
  bool stopping_ = false;
};

}  // namespace demlink::server
