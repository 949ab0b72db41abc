#pragma once
/// The co-simulation on LIGGGHTS under MPI (docs/scale-out.md "Co-simulation"): rank 0
/// alone speaks TCP and the protocol; every other rank runs a mirror CosimHost that takes
/// the same events in the same order, so it compiles the same world and makes the same
/// LIGGGHTS calls in lockstep.
///
/// Why events: the host is deterministic for a given sequence of events (what a session
/// recording holds: connections, messages, and markers for the time-driven decisions),
/// so forwarding them reproduces every decision without a second protocol. Rank 0 collects
/// them as they come and broadcasts them in ONE batch just before its simulation next
/// calls the engine (CosimOptions::before_engine): a whole interval's packages of every
/// body travel together. Only then must the other ranks catch up, because the engine's
/// calls are collectives; between two engine calls the mirrors need nothing. A batch is
/// only sent when it holds events, and the mirrors wait for the next batch only after
/// acting on the last, so the broadcasts and LIGGGHTS's collectives pair up in the same
/// order on every rank.
///
/// Between every two steps of an interval rank 0 also broadcasts whether to go on
/// (CosimOptions::stop_consensus): a shutdown cuts the interval at the same step on every
/// rank, which then takes the shutdown from the next batch and writes the final
/// checkpoint together.
#include <string>

#include "demlink/server/cosim/cosim_host.hpp"

namespace demlink::server {

/// Rank 0's side.
class LockstepLeader {
 public:
  LockstepLeader() = default;
  /// Tells the mirrors to stop (close()) if that was not done.
  ~LockstepLeader();
  LockstepLeader(const LockstepLeader&) = delete;
  LockstepLeader& operator=(const LockstepLeader&) = delete;

  /// Sets options.on_event and options.before_engine to this leader (which must outlive
  /// the host).
  void attach(CosimOptions& options);
  /// Appends an event to the next batch.
  void add(const v1::SessionEvent& event);
  /// Broadcasts the collected events as one batch, if there are any (a collective).
  void flush();
  /// Tells the mirrors to stop (after flushing).
  void close();

 private:
  std::string batch_;  ///< length-prefixed serialised SessionEvents
  bool closed_ = false;
};

/// Ranks > 0: a mirror host (options.mirror, no output files, its output root a scratch
/// folder removed at the end) replays rank 0's batches until rank 0 closes.
void runLockstepMirror(CosimOptions options);

}  // namespace demlink::server
