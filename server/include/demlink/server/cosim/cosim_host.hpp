#pragma once
/// The co-simulation, independent of the transport (DESIGN.md, "Co-simulation protocol").
///
/// The network layer (server/src/net) decodes frames into ClientMessages, checks Hello
/// (protocol version, access token) and hands everything else here through the interface it
/// owns (net/session_handler.hpp), which the host implements; what comes back is the list of
/// messages to send. Being transport-free, the whole protocol (compiler, scheduler,
/// motion coupling, outputs, faults) is testable in-process, and a recorded session can be
/// replayed without a network (recorder).
///
/// One simulation at a time. It collects declarations (the scene file's plus the clients'
/// that named the same Hello.simulation as the first one), compiles when the
/// SimulationBox's expected set is complete, when every connection said DeclarationsDone,
/// or after the quiet period (or gives up after
/// the assembly timeout),
/// answers every connection with Compiled, then runs the sample grid: at each step where
/// components are due it waits for exactly those, advances the world to the next due step
/// and answers each component whose interval ended there. It ends when every connection
/// said Bye, the end step is reached, a fault happens, or shutdown(); then outputs are
/// flushed and the host is ready for the next simulation (new connections).
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "demlink/server/backend/simulation_backend.hpp"
#include "demlink/server/cosim/particle_memory_ledger.hpp"
#include "demlink/server/net/session_handler.hpp"
#include "demlink/server/scene/input_limits.hpp"
#include "demlink/v1/protocol.pb.h"
#include "demlink/v1/recording.pb.h"
#include "demlink/v1/scene.pb.h"

namespace demlink::core {
class World;
}

namespace demlink::server {

class SteppingTurns;

struct CosimOptions {
  v1::Scene base_scene;                         ///< components from a scene file (may be empty)
  std::filesystem::path scene_directory = ".";  ///< anchors relative paths (scene file, stl_file)
  /// Folder the files a client names (stl_file, particle_file.path, ...) must lie in
  /// (relative paths are relative to it); none: a client may name no file.
  std::optional<std::filesystem::path> data_root;
  /// Simulation N writes into output_root/sim_NNN: the first such folder at or after N that
  /// does not exist yet, so a restarted server never writes into an earlier run's folder.
  std::filesystem::path output_root = "out/cosim";
  /// Simulation N writes into output_root/sim_NNN even if it exists (numbering starts at
  /// 001 with each server start; files of the same name are overwritten).
  bool overwrite = false;
  double quiet_period_s = 2.0;     ///< compile this long after the last Declare when nothing is expected
  double client_timeout_s = 30.0;  ///< a due component's package may take this long [s]
  /// A pending simulation not compiled this long after its first client joined ends with
  /// TIMEOUT to its clients, so a set that never completes cannot hold the server [s]; 0: never.
  double assembly_timeout_s = 60.0;
  /// A running simulation logs a progress line this often [s]; 0: never.
  double progress_interval_s = 10.0;
  std::filesystem::path record_file;  ///< non-empty: append every received message (docs/protocol.md)
  std::string server_name = "demlink-server";
  /// The engine (demlink-server --backend). A SimulationBox.backend that differs from it
  /// is refused at the compile; on LIGGGHTS, what it cannot run is refused there too
  /// (requireLiggghtsCompatible).
  BackendKind backend = BackendKind::Native;
  /// Builds the LIGGGHTS engine of a compiled world, writing its log to the given file
  /// (the second path) and starting from the given checkpoint's restart files (the third;
  /// empty: from the world); set by demlink-server when it is built with the LIGGGHTS backend.
  std::function<std::unique_ptr<SimulationBackend>(core::World&, const std::filesystem::path&,
                                                   const std::filesystem::path&)>
      liggghts;
  /// Non-empty: the first simulation compiled continues from this checkpoint of a
  /// co-simulation with the same declarations (demlink-server --restore; docs/cosim.md
  /// "Restoring a checkpoint"); later ones start at step 0.
  std::filesystem::path restore_file;
  /// Called with every event as the host takes it, before it acts on it (the events a
  /// recording holds; elapsed_s not set). Under MPI, rank 0 forwards them to the other
  /// ranks, whose hosts replay them (docs/scale-out.md "Co-simulation").
  std::function<void(const v1::SessionEvent&)> on_event;
  /// Called before the running simulation calls its engine, which every MPI rank must
  /// do together: rank 0 broadcasts the events collected since the last call.
  std::function<void()> before_engine;
  /// Told once when a simulation starts, before its first step_observer call, with its
  /// name: its output folder's, "sim_003" (the live view's list, LiveViewHub::announce).
  std::function<void(const core::World&, const std::string&)> open_observer;
  /// Sees the running simulation's world after every step and at its start (the live view,
  /// LiveViewHub::offer); it must not change the world.
  std::function<void(const core::World&)> step_observer;
  /// Told once when the simulation closes, after its last step_observer call
  /// (LiveViewHub::release); it must not change the world.
  std::function<void(const core::World&)> close_observer;
  /// This host mirrors rank 0's on another MPI rank: it drives the engine in lockstep but
  /// writes no output files.
  bool mirror = false;
  /// The number of this host's first simulation (Welcome.simulation_number, the output
  /// folder sim_NNN); the SimulationHub gives each simulation its own host and number.
  std::uint64_t first_simulation_number = 1;
  /// Set: stepping stops at the next step boundary once it is true (server shutdown), so
  /// an interval of any length is cut short; the host then ends on shutdown(). Another
  /// thread sets it while this host steps.
  std::shared_ptr<const std::atomic<bool>> stop_stepping;
  /// Set (LIGGGHTS under MPI): called between every two steps of an interval with this
  /// rank's wish to stop (stop_stepping or the turns); returns the decision every rank
  /// takes, rank 0's (cosim_lockstep.hpp), so all ranks cut an interval at the same step.
  std::function<bool(bool)> stop_consensus;
  /// Set: the simulation steps only while it holds a turn (stepping_turns.hpp), shared by
  /// every simulation of the server.
  std::shared_ptr<SteppingTurns> turns;
  /// The ledger a native simulation's particle memory is reserved in while it runs,
  /// shared by every simulation of the server; unset: the process's own
  /// (processParticleMemory()).
  std::shared_ptr<ParticleMemoryLedger> particle_memory;
};

class CosimHost final : public SessionHandler {
 public:
  explicit CosimHost(CosimOptions options);
  ~CosimHost() override;
  CosimHost(const CosimHost&) = delete;
  CosimHost& operator=(const CosimHost&) = delete;

  /// A connection passed Hello (version and token already checked): Welcome, or an
  /// Error when it cannot join (e.g. a simulation is already running).
  std::vector<Outgoing> connected(ConnectionId id, const v1::Hello& hello, SteadyClock::time_point now) override;
  /// Declare, DataPackage or Bye from a welcomed connection (a second Hello is OUT_OF_ORDER).
  std::vector<Outgoing> received(ConnectionId from, const v1::ClientMessage& message,
                                 SteadyClock::time_point now) override;
  /// The connection is gone (EOF, reset, bad frame): ends its simulation if it took part.
  std::vector<Outgoing> disconnected(ConnectionId id, const std::string& why, SteadyClock::time_point now) override;
  /// Timers: quiet period over -> compile; a due client silent past the timeout -> TIMEOUT.
  std::vector<Outgoing> poll(SteadyClock::time_point now) override;
  /// When poll() next has something to do; nullopt: nothing scheduled.
  [[nodiscard]] std::optional<SteadyClock::time_point> nextDeadline() const override;
  /// SIGINT/SIGTERM: flush outputs, write a checkpoint, tell every client (SERVER_SHUTDOWN).
  std::vector<Outgoing> shutdown(const std::string& reason, SteadyClock::time_point now) override;
  /// Compiles the pending declarations now, as poll() does when the quiet period is over
  /// (the session replay calls it at a recorded COMPILE_NOW marker). Nothing if none pending.
  std::vector<Outgoing> compileNow(SteadyClock::time_point now);
  /// Every component due now whose package is missing times out, as poll() does after the
  /// client timeout (the session replay calls it at a recorded TIMEOUT marker).
  std::vector<Outgoing> expireWaitNow(SteadyClock::time_point now);
  /// The pending simulation ends with TIMEOUT to its clients, as poll() does after the
  /// assembly timeout (the session replay calls it at a recorded ASSEMBLY_TIMEOUT marker).
  std::vector<Outgoing> expireAssemblyNow(SteadyClock::time_point now);
  /// The running simulation's world, for tests and in-process drivers; null when none runs.
  [[nodiscard]] const core::World* world() const;
  /// The running simulation (components, couplings, scheduler); null when none runs.
  [[nodiscard]] const class CosimSimulation* simulation() const;
  /// A simulation has been compiled and not yet ended.
  [[nodiscard]] bool simulationRunning() const;
  /// Simulations ended so far [-].
  [[nodiscard]] std::uint64_t simulationsFinished() const;

  /// Who holds the pending or running simulation, for a client that cannot join it.
  struct Status {
    std::uint64_t number = 0;  ///< the pending or running simulation's number
    bool running = false;      ///< compiled (else pending, or none when `clients` is empty)
    std::string group;         ///< its clients' Hello.simulation
    std::vector<std::pair<ConnectionId, std::string>> clients;  ///< connection and client name
    std::optional<SteadyClock::time_point> assembly_deadline;   ///< pending: when it times out
  };
  [[nodiscard]] Status status() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace demlink::server
