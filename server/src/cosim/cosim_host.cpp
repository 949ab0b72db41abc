/// The transport-free co-simulation host (contract in cosim_host.hpp; semantics in
/// docs/cosim.md).
///
/// States: no simulation (waiting for connections), collecting (connections declare; the
/// compiler decides when to compile), running (the sample grid). Every way a simulation
/// can end goes through endSimulation(): outputs are flushed, every connection still in the
/// simulation gets Finished (and is closed), the compiler returns to the scene file's
/// declarations and the simulation counter advances, so the next connection starts the
/// next simulation. Fault policy: any protocol violation or invalid input by a client ends
/// the simulation it belongs to (fatal Error to it, PEER_DISCONNECTED naming it to the
/// others); the server itself stays up. A Declare that is merely refused (unknown kind,
/// duplicate name, second simulation box) is not fatal: the client may declare again.
#include "demlink/server/cosim/cosim_host.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "demlink/core/base/log_text.hpp"
#include "demlink/core/base/names.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/server/backend/liggghts_script.hpp"
#include "demlink/server/cosim/cosim_compiler.hpp"
#include "demlink/server/cosim/cosim_simulation.hpp"
#include "demlink/server/cosim/session_recorder.hpp"
#include "demlink/server/run/output_directory.hpp"

namespace demlink::server {
namespace {

/// Longest server-built message (it may quote several names) in a log line [bytes].
constexpr std::size_t kLogMessageMaxBytes = 4096;

struct Connection {
  std::string name;
  bool declared = false;  ///< declared at least one component
  bool declarations_done = false;  ///< sent DeclarationsDone
  bool said_bye = false;  ///< got its Finished already
};

/// A wait as a clock duration, clamped to [0, kMaxWaitSeconds]: a time_point plus a
/// longer duration could overflow the clock's 64-bit count (1e308 s would be "now").
SteadyClock::duration seconds(double s) {
  const double clamped = std::isfinite(s) ? std::clamp(s, 0.0, kMaxWaitSeconds) : kMaxWaitSeconds;
  return std::chrono::duration_cast<SteadyClock::duration>(std::chrono::duration<double>(clamped));
}

}  // namespace

struct CosimHost::Impl {
  explicit Impl(CosimOptions o) : options(std::move(o)), compiler(options.base_scene) {
    if (!options.record_file.empty()) recorder = std::make_unique<SessionRecorder>(options.record_file, options);
  }

  CosimOptions options;
  CosimCompiler compiler;
  std::map<ConnectionId, Connection> connections;
  std::unique_ptr<CosimSimulation> sim;
  /// The running simulation's particle memory in the server's ledger (native only).
  std::optional<ParticleMemoryLedger::Reservation> memory;
  std::uint64_t finished = 0;
  std::optional<SteadyClock::time_point> quiet_since;
  std::optional<SteadyClock::time_point> waiting_since;
  /// The pending simulation's first client joined then (set while assembling only).
  std::optional<SteadyClock::time_point> assembling_since;
  /// Hello.simulation of the pending or running simulation's clients.
  std::string group;
  /// Progress line: when the next is due, and the figures at the last one.
  struct Progress {
    SteadyClock::time_point next;
    SteadyClock::time_point last;
    std::uint64_t step = 0;
    std::uint64_t exchanges = 0;
  };
  std::optional<Progress> progress;
  std::uint64_t exchanges = 0;  ///< packages accepted in the running simulation [-]
  std::unique_ptr<SessionRecorder> recorder;

  // --- recording -----------------------------------------------------------------
  void record(v1::SessionEvent::Kind kind, ConnectionId id = 0, const v1::ClientMessage* message = nullptr,
              const std::string& text = {}) {
    if (!recorder && !options.on_event) return;
    v1::SessionEvent event;
    event.set_kind(kind);
    event.set_connection(id);
    if (message != nullptr) *event.mutable_message() = *message;
    event.set_text(text);
    if (options.on_event) options.on_event(event);
    if (!recorder) return;
    try {
      recorder->record(std::move(event));
    } catch (const std::exception& error) {
      spdlog::error("session recorder: {}; recording stopped", error.what());
      recorder.reset();
    }
  }

  // --- sending -------------------------------------------------------------------
  static void send(std::vector<Outgoing>& out, ConnectionId to, const v1::Error& error, bool close = false) {
    Outgoing o;
    o.to = to;
    *o.message.mutable_error() = error;
    o.close_after = close;
    out.push_back(std::move(o));
  }

  [[nodiscard]] std::string clientName(ConnectionId id) const {
    const auto it = connections.find(id);
    const std::string name =
        it != connections.end() && !it->second.name.empty() ? core::quotedLogText(it->second.name) : "(unnamed)";
    return fmt::format("{} (connection {})", name, id);
  }

  /// The components `missing` and their clients, the first few of them (a list of any
  /// length stays a short line).
  [[nodiscard]] std::string waitedFor(const std::vector<std::size_t>& missing) const {
    constexpr std::size_t kShown = 5;
    std::string names;
    for (std::size_t k = 0; k < missing.size() && k < kShown; ++k) {
      const CosimComponent& c = sim->components()[missing[k]];
      names += (k == 0 ? "" : ", ") + core::quotedLogText(c.name) + " of client " + clientName(*c.owner);
    }
    if (missing.size() > kShown) {
      names += fmt::format(" and {} more ({} in all)", missing.size() - kShown, missing.size());
    }
    return names;
  }

  [[nodiscard]] std::uint64_t number() const { return options.first_simulation_number + finished; }

  [[nodiscard]] v1::Finished finishedMessage(const std::string& reason) const {
    v1::Finished f;
    if (sim) {
      f.set_step(sim->scheduler().currentStep());
      f.set_time(static_cast<double>(f.step()) * sim->compiled().time_step);
      f.set_output_directory(sim->outputDirectory().string());
    }
    f.set_reason(reason);
    return f;
  }

  void sendFinished(std::vector<Outgoing>& out, ConnectionId to, const std::string& reason) const {
    Outgoing o;
    o.to = to;
    *o.message.mutable_finished() = finishedMessage(reason);
    o.close_after = true;
    out.push_back(std::move(o));
  }

  // --- lifecycle -----------------------------------------------------------------
  /// Ends the current (pending or running) simulation: outputs flushed, Finished to
  /// every connection that has not had one, ready for the next simulation.
  void endSimulation(std::vector<Outgoing>& out, const std::string& reason) {
    if (sim) {
      try {
        sim->finish(reason);
      } catch (const std::exception& error) {
        spdlog::error("simulation {}: final output failed: {}", number(), error.what());
      }
      // The world's step: a shutdown may cut an interval short past the last exchange.
      const core::World& w = sim->compiled().scene->world;
      spdlog::info("simulation {} ended at step {} (t = {:.6g} s): {}; output in {}", number(), w.stepCount(),
                   w.time(), reason, sim->outputDirectory().string());
    } else {
      spdlog::info("simulation {} ended before it was compiled: {}", number(), reason);
    }
    for (const auto& [id, connection] : connections) {
      if (!connection.said_bye) sendFinished(out, id, reason);
    }
    connections.clear();
    sim.reset();
    memory.reset();
    compiler.reset();
    quiet_since.reset();
    waiting_since.reset();
    assembling_since.reset();
    group.clear();
    progress.reset();
    exchanges = 0;
    ++finished;
  }

  /// A client broke the protocol or sent invalid input: fatal Error to it, the cause to
  /// the others (`othersCode`), then the simulation ends.
  void fault(std::vector<Outgoing>& out, ConnectionId offender, v1::Error error,
             v1::Error::Code othersCode = v1::Error::PEER_DISCONNECTED) {
    error.set_fatal(true);
    spdlog::warn("simulation {}: client {}: {} ({}{}{})", number(), clientName(offender),
                 core::logText(error.message(), kLogMessageMaxBytes),
                 v1::Error::Code_Name(error.code()), error.field().empty() ? "" : ", field ", error.field());
    send(out, offender, error);
    if (!sim) {
      // Before the compile the offender only leaves: a stray or broken client cannot end
      // an assembly that others are building.
      sendFinished(out, offender, "left before the compile: " + error.message());
      leaveAssembly(offender);
      return;
    }
    const std::string cause = "client " + clientName(offender) + ": " + error.message();
    for (const auto& [id, connection] : connections) {
      if (id == offender || connection.said_bye) continue;
      send(out, id, makeError(othersCode, "the simulation ended: " + cause, error.component(), error.field(), true));
    }
    endSimulation(out, cause);
  }

  /// Reserves the compiled world's particle memory in the server's ledger (`memory`), or
  /// says why not: the simulations running now hold too much of the budget. LIGGGHTS runs
  /// one simulation at a time (checked against the budget as its scene was translated),
  /// and its MPI mirrors must decide as rank 0 does, so only native simulations reserve.
  [[nodiscard]] std::optional<v1::Error> reserveMemory(const CompiledSimulation& compiled) {
    if (options.backend != BackendKind::Native || options.mirror) return std::nullopt;
    const std::shared_ptr<ParticleMemoryLedger>& ledger =
        options.particle_memory ? options.particle_memory : processParticleMemory();
    const std::uint64_t need = particleMemoryEstimate(compiled.scene->world);
    if (std::optional<ParticleMemoryLedger::Reservation> held = ParticleMemoryLedger::reserve(ledger, need)) {
      memory.emplace(std::move(*held));
      return std::nullopt;
    }
    return makeError(v1::Error::SERVER_BUSY,
                     fmt::format("this simulation needs about {:.3g} GB for its particles and nodes; the simulations "
                                 "running now hold {:.3g} GB of this server's {:.3g} GB (half of its memory or "
                                 "address-space limit); connect again when one has finished",
                                 static_cast<double>(need) * 1e-9, static_cast<double>(ledger->held()) * 1e-9,
                                 static_cast<double>(ledger->budget()) * 1e-9),
                     "", "", true);
  }

  /// What the engine refuses of a compiled set: a SimulationBox.backend other than the
  /// server's, and on LIGGGHTS what it cannot run; nullopt if it runs.
  [[nodiscard]] std::optional<v1::Error> refusedByBackend(const CompiledSimulation& compiled) const {
    v1::Scene declared;
    for (const DeclaredComponent& d : compiler.declarations()) *declared.add_components() = d.declaration;
    // Both checks name fields "components[i]..." of `declared`, in the declarations' order.
    const auto refusedAs = [&](const core::InputError& error, const std::string& prefix) {
      const NamedField named = nameDeclaredField(error.field(), compiler.declarations());
      const std::string component =
          named.component ? compiler.declarations()[*named.component].declaration.name() : std::string();
      const core::InputError renamed(named.field, error.value(), error.reason());
      return makeError(v1::Error::INVALID_DECLARATION, prefix + renamed.what(), component, named.field, true);
    };
    try {
      requireBackendAgrees(declared, options.backend);
    } catch (const core::InputError& disagreement) {
      return refusedAs(disagreement, "");
    }
    if (options.backend != BackendKind::Liggghts) return std::nullopt;
    if (!options.liggghts) {
      return makeError(v1::Error::INTERNAL, "this server has no LIGGGHTS backend", "", "", true);
    }
    try {
      requireLiggghtsCompatible(declared, compiled.scene->world);
    } catch (const core::InputError& refusal) {
      return refusedAs(refusal, "LIGGGHTS backend: ");
    }
    return std::nullopt;
  }

  void compile(std::vector<Outgoing>& out, SteadyClock::time_point now) {
    const SteadyClock::time_point workStart = SteadyClock::now();
    CompiledSimulation compiled;
    try {
      compiled = compiler.compile(options.scene_directory, options.data_root);
    } catch (const CompileFailure& failure) {
      spdlog::error("simulation {}: compile failed: {}", number(),
                    core::logText(failure.error.message(), kLogMessageMaxBytes));
      for (const auto& [id, connection] : connections) send(out, id, failure.error);
      endSimulation(out, "compile failed: " + failure.error.message());
      return;
    }
    if (std::optional<v1::Error> refused = refusedByBackend(compiled)) {
      spdlog::error("simulation {}: compile failed: {}", number(),
                    core::logText(refused->message(), kLogMessageMaxBytes));
      for (const auto& [id, connection] : connections) send(out, id, *refused);
      endSimulation(out, "compile failed: " + refused->message());
      return;
    }
    if (std::optional<v1::Error> refused = reserveMemory(compiled)) {
      spdlog::warn("simulation {}: not started: {}", number(), core::logText(refused->message(), kLogMessageMaxBytes));
      for (const auto& [id, connection] : connections) send(out, id, *refused);
      endSimulation(out, "not started: " + refused->message());
      return;
    }
    std::filesystem::path directory;
    try {
      // Never an earlier simulation's folder, unless told to overwrite (output_directory.hpp).
      compiled.scene->run.overwrite = options.overwrite;
      const std::uint64_t folder =
          options.overwrite ? number() : claimSimulationDirectory(options.output_root, number());
      directory = simulationDirectory(options.output_root, folder);
      sim = std::make_unique<CosimSimulation>(std::move(compiled), directory, options);
      options.restore_file.clear();  // the first simulation only
    } catch (const std::exception& error) {
      options.restore_file.clear();
      const v1::Error e = makeError(v1::Error::INTERNAL, std::string("cannot start the simulation: ") + error.what(),
                                    "", "", true);
      for (const auto& [id, connection] : connections) send(out, id, e);
      endSimulation(out, e.message());
      return;
    }
    const CompiledSimulation& c = sim->compiled();
    spdlog::info("simulation {} compiled:\n{}", number(), c.report.text());
    spdlog::info("simulation {} starts with {} connections -> {}", number(), connections.size(), directory.string());
    for (const auto& [id, connection] : connections) {
      Outgoing o;
      o.to = id;
      v1::Compiled& m = *o.message.mutable_compiled();
      for (const CosimComponent& component : c.components) {
        v1::CompiledComponent entry;
        entry.set_name(component.name);
        entry.set_id(component.id);
        entry.set_kind(component.kind);
        entry.set_interval_steps(component.interval_steps);
        entry.set_remote(component.owner.has_value());
        if (component.owner == id) *m.add_components() = entry;
        *m.add_all_components() = entry;
      }
      m.set_time_step(c.time_step);
      m.set_end_step(c.end_step);
      m.set_start_step(sim->world().stepCount());
      *m.mutable_report() = c.report;
      for (v1::DataPackage& p : sim->initialOutputs(id)) *m.add_initial_outputs() = std::move(p);
      out.push_back(std::move(o));
    }
    quiet_since.reset();
    run(out, now + (SteadyClock::now() - workStart));
  }

  /// Advances while every due component has reported. The clients' time to answer
  /// (timeout()) starts when this call's answers leave, after its work: `now` is when the
  /// message that triggered it arrived, and a compile that generates a large pit, or many
  /// steps to the next exchange, can take longer than the timeout itself (seen under
  /// ASan: the 60 s had passed before Compiled was sent). The elapsed time is measured on
  /// the real clock and added to `now`, so tests that drive `now` by hand keep their times.
  void run(std::vector<Outgoing>& out, SteadyClock::time_point now) {
    const SteadyClock::time_point workStart = SteadyClock::now();
    advanceWhileComplete(out);
    if (sim) {
      waiting_since = now + (SteadyClock::now() - workStart);
      if (!progress) logProgress(now);  // starts the progress clock
    }
  }

  void advanceWhileComplete(std::vector<Outgoing>& out) {
    while (sim && sim->scheduler().complete()) {
      CosimSimulation::Advance advance = sim->advance();
      for (auto& [to, package] : advance.answers) {
        Outgoing o;
        o.to = to;
        *o.message.mutable_data() = std::move(package);
        out.push_back(std::move(o));
      }
      if (advance.interrupted) return;  // the server stops: shutdown() ends the simulation
      if (advance.end_reached) {
        endSimulation(out, "end time reached");
        return;
      }
      if (!advance.stepped) return;  // nothing exchanged and no end step: until every client said Bye
    }
  }

  [[nodiscard]] double timeout() const {
    return sim && sim->compiled().client_timeout_s > 0.0 ? sim->compiled().client_timeout_s : options.client_timeout_s;
  }

  /// The simulation ends when every connection that declared components said Bye (when
  /// none declared any: every connection).
  [[nodiscard]] bool everyoneSaidBye() const {
    bool anyDeclared = false;
    for (const auto& [id, c] : connections) anyDeclared = anyDeclared || c.declared;
    for (const auto& [id, c] : connections) {
      if ((c.declared || !anyDeclared) && !c.said_bye) return false;
    }
    return true;
  }

  /// Some connection announced DeclarationsDone: it promises to say when it is done, so
  /// the quiet period (a guess) no longer decides the compile.
  [[nodiscard]] bool anyDeclarationsDone() const {
    return std::any_of(connections.begin(), connections.end(),
                       [](const auto& entry) { return entry.second.declarations_done; });
  }

  [[nodiscard]] bool usesQuietPeriod() const { return compiler.usesQuietPeriod() && !anyDeclarationsDone(); }

  /// The declared set is complete: the SimulationBox's expected set, or every connection
  /// of the pending simulation said DeclarationsDone.
  [[nodiscard]] bool readyToCompile() const {
    if (connections.empty()) return false;
    if (compiler.expectedSetComplete()) return true;
    return std::all_of(connections.begin(), connections.end(),
                       [](const auto& entry) { return entry.second.declarations_done; });
  }

  // --- events --------------------------------------------------------------------
  void onDeclare(std::vector<Outgoing>& out, ConnectionId from, const v1::Declare& declare,
                 SteadyClock::time_point now) {
    if (sim) {
      fault(out, from,
            makeError(v1::Error::OUT_OF_ORDER,
                      "Declare of " + core::quotedLogText(declare.component().name()) +
                          " after Compiled: the simulation is running",
                      declare.component().name(), "declare"));
      return;
    }
    if (compiler.isRepeat(from, declare.component())) {
      // A tool that runs its initialisation twice declares the same component again.
      spdlog::info("client {} repeated the declaration of {} (ignored)", clientName(from),
                   core::quotedLogText(declare.component().name()));
      return;
    }
    if (std::optional<v1::Error> refused = compiler.declare(from, declare.component())) {
      spdlog::warn("client {}: declaration refused: {}", clientName(from),
                   core::logText(refused->message(), kLogMessageMaxBytes));
      send(out, from, *refused);
      return;
    }
    connections[from].declared = true;
    quiet_since = now;
    spdlog::info("client {} declared {}", clientName(from), core::quotedLogText(declare.component().name()));
    if (readyToCompile()) compile(out, now);
  }

  void onDeclarationsDone(std::vector<Outgoing>& out, ConnectionId from, SteadyClock::time_point now) {
    if (sim) return;  // a repeat after the compile: nothing left to decide
    Connection& connection = connections[from];
    if (connection.declarations_done) return;
    connection.declarations_done = true;
    spdlog::info("client {}: declarations done", clientName(from));
    if (readyToCompile()) compile(out, now);
  }

  void onData(std::vector<Outgoing>& out, ConnectionId from, const v1::DataPackage& package,
              SteadyClock::time_point now) {
    if (!sim) {
      fault(out, from,
            makeError(v1::Error::OUT_OF_ORDER, "DataPackage before Compiled (component id " +
                                                   std::to_string(package.component_id()) + ")",
                      "", "data"));
      return;
    }
    if (std::optional<v1::Error> bad = sim->accept(from, package)) {
      fault(out, from, *bad);
      return;
    }
    ++exchanges;
    if (sim->scheduler().complete()) run(out, now);
  }

  /// A connection leaves the pending simulation: its declarations are withdrawn; the last
  /// one to leave returns the host to waiting for a new simulation.
  void leaveAssembly(ConnectionId id) {
    compiler.withdraw(id);
    connections.erase(id);
    if (connections.empty()) {
      compiler.reset();
      quiet_since.reset();
      assembling_since.reset();
      group.clear();
    }
  }

  void onBye(std::vector<Outgoing>& out, ConnectionId from, const v1::Bye& bye, SteadyClock::time_point now) {
    spdlog::info("client {} said Bye{}{}", clientName(from), bye.reason().empty() ? "" : ": ",
                 core::logText(bye.reason()));
    if (!sim) {
      sendFinished(out, from, "said Bye before the simulation was compiled");
      leaveAssembly(from);
      if (readyToCompile()) compile(out, now);
      return;
    }
    Connection& connection = connections[from];
    connection.said_bye = true;
    sim->retire(from);
    sendFinished(out, from, "said Bye");
    if (everyoneSaidBye()) {
      endSimulation(out, "all clients said Bye");
      return;
    }
    if (sim->compiled().end_step == 0 && !sim->scheduler().anyActive()) {
      // Nothing exchanged any more and no end time: the world could never advance again,
      // and the clients left would hold the server for as long as they stay connected.
      endSimulation(out, "no component is exchanged any more and there is no end time");
      return;
    }
    if (sim->scheduler().complete()) run(out, now);
  }

  void onDisconnect(std::vector<Outgoing>& out, ConnectionId id, const std::string& why,
                    SteadyClock::time_point now) {
    const auto it = connections.find(id);
    if (it == connections.end()) return;
    const Connection connection = it->second;
    if (!sim) {
      spdlog::info("client {} left before the compile ({})", clientName(id), why);
      leaveAssembly(id);
      // The one not done may have left: the others' DeclarationsDone now completes the set.
      if (anyDeclarationsDone() && readyToCompile()) compile(out, now);
      return;
    }
    if (connection.said_bye) {
      connections.erase(id);
      return;
    }
    if (!connection.declared) {
      connections.erase(id);
      if (connections.empty() || everyoneSaidBye()) endSimulation(out, "every client left");
      return;
    }
    const std::string cause = "client " + clientName(id) + " disconnected: " + why;
    spdlog::warn("simulation {}: {}", number(), cause);
    connections.erase(id);
    for (const auto& [other, c] : connections) {
      if (!c.said_bye) send(out, other, makeError(v1::Error::PEER_DISCONNECTED, cause, "", "", true));
    }
    endSimulation(out, cause);
  }

  void expire(std::vector<Outgoing>& out) {
    if (!sim) return;
    const std::vector<std::size_t> missing = sim->scheduler().missing();
    if (missing.empty()) return;
    const std::uint64_t step = sim->scheduler().currentStep();
    const std::string names = waitedFor(missing);
    const std::string cause = fmt::format("no package for step {} within {} s from {}", step, timeout(), names);
    spdlog::warn("simulation {}: timeout: {}", number(), cause);
    std::map<ConnectionId, std::string> offenders;
    for (const std::size_t index : missing) {
      const CosimComponent& c = sim->components()[index];
      offenders.emplace(*c.owner, c.name);
    }
    for (const auto& [id, connection] : connections) {
      if (connection.said_bye) continue;
      const auto offender = offenders.find(id);
      send(out, id,
           makeError(v1::Error::TIMEOUT, offender != offenders.end() ? "you did not answer: " + cause : cause,
                     offender != offenders.end() ? offender->second : sim->components()[missing.front()].name,
                     "data.step", true));
    }
    endSimulation(out, "timeout: " + cause);
  }

  /// The pending simulation did not complete within the assembly timeout: TIMEOUT naming
  /// what is missing to every client of it, then it ends (no output directory).
  void expireAssembly(std::vector<Outgoing>& out) {
    if (sim || connections.empty()) return;
    const CosimCompiler::Missing missing = compiler.missing();
    const std::string cause = fmt::format("simulation {} was not compiled within {} s of its first client: {}",
                                          number(), options.assembly_timeout_s, missing.what);
    spdlog::warn("{}", cause);
    for (const auto& [id, connection] : connections) {
      send(out, id, makeError(v1::Error::TIMEOUT, cause, "", missing.field, true));
    }
    endSimulation(out, "assembly timeout: " + missing.what);
  }

  /// ", whose assembly times out in S s" (nothing without an assembly timeout).
  [[nodiscard]] std::string assemblyTimeLeft(SteadyClock::time_point now) const {
    const std::optional<SteadyClock::time_point> deadline = assemblyDeadline();
    if (!deadline) return {};
    return fmt::format(", whose assembly times out in {:.1f} s",
                       std::max(0.0, std::chrono::duration<double>(*deadline - now).count()));
  }

  [[nodiscard]] std::optional<SteadyClock::time_point> assemblyDeadline() const {
    if (sim || !assembling_since || options.assembly_timeout_s <= 0.0) return std::nullopt;
    return *assembling_since + seconds(options.assembly_timeout_s);
  }

  /// One line for an operator: simulated time, rates since the last line, particles, and
  /// whom the world waits for.
  void logProgress(SteadyClock::time_point now) {
    if (!sim || options.progress_interval_s <= 0.0) return;
    const std::uint64_t step = sim->scheduler().currentStep();
    if (!progress) {
      progress = Progress{now + seconds(options.progress_interval_s), now, step, exchanges};
      return;
    }
    const double elapsed = std::chrono::duration<double>(now - progress->last).count();
    const double stepsPerSecond = elapsed > 0.0 ? static_cast<double>(step - progress->step) / elapsed : 0.0;
    const double exchangesPerSecond =
        elapsed > 0.0 ? static_cast<double>(exchanges - progress->exchanges) / elapsed : 0.0;
    std::string waiting = "nothing";
    const std::vector<std::size_t> missing = sim->scheduler().missing();
    if (!missing.empty()) {
      waiting = waitedFor(missing);
      if (waiting_since) {
        waiting += fmt::format(" for {:.1f} s", std::chrono::duration<double>(now - *waiting_since).count());
      }
    }
    const CompiledSimulation& c = sim->compiled();
    spdlog::info("simulation {}: t = {:.6g} s (step {}{}), {} particles, {:.0f} steps/s, {:.1f} exchanges/s, "
                 "waiting for {}",
                 number(), static_cast<double>(step) * c.time_step, step,
                 c.end_step > 0 ? fmt::format(" of {}", c.end_step) : std::string(),
                 c.scene->world.particles().size(), stepsPerSecond, exchangesPerSecond, waiting);
    *progress = Progress{now + seconds(options.progress_interval_s), now, step, exchanges};
  }

  template <class Body>
  std::vector<Outgoing> guarded(Body body) {
    std::vector<Outgoing> out;
    try {
      body(out);
    } catch (const std::exception& error) {
      // A watchdog stop is the world refusing to go on, not a bug: its own code, the check as the field.
      const auto* fault = dynamic_cast<const core::SimulationFault*>(&error);
      // An input refused by the engine as it is applied, where it depends on the world (the
      // frame's centrifugal acceleration at the farthest particle): the client's, not ours.
      const auto* input = dynamic_cast<const core::InputError*>(&error);
      const char* what = fault != nullptr ? "stopped" : input != nullptr ? "input refused" : "internal error";
      spdlog::error("simulation {}: {}: {}", number(), what, core::logText(error.what(), kLogMessageMaxBytes));
      v1::Error e;
      if (fault != nullptr) {
        e = makeError(v1::Error::SIMULATION_FAULT, error.what(), "", "watchdog." + fault->check(), true);
      } else if (input != nullptr) {
        e = makeError(v1::Error::INVALID_INPUT, error.what(), "", input->field(), true);
      } else {
        e = makeError(v1::Error::INTERNAL, std::string("internal error: ") + error.what(), "", "", true);
      }
      for (const auto& [id, connection] : connections) {
        if (!connection.said_bye) send(out, id, e);
      }
      try {
        endSimulation(out, e.message());
      } catch (const std::exception& again) {
        spdlog::error("ending the simulation failed too: {}", again.what());
        connections.clear();
        sim.reset();
        memory.reset();
        compiler.reset();
      }
    }
    return out;
  }
};

CosimHost::CosimHost(CosimOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}

CosimHost::~CosimHost() = default;

std::vector<Outgoing> CosimHost::connected(ConnectionId id, const v1::Hello& hello,
                                                  SteadyClock::time_point now) {
  Impl& s = *impl_;
  v1::ClientMessage message;
  *message.mutable_hello() = hello;
  s.record(v1::SessionEvent::CONNECTED, id, &message);
  return s.guarded([&](std::vector<Outgoing>& out) {
    if (s.connections.contains(id)) {
      s.fault(out, id, makeError(v1::Error::OUT_OF_ORDER, "a second Hello on the same connection", "", "hello"));
      return;
    }
    if (s.sim) {
      s.send(out, id,
             makeError(v1::Error::OUT_OF_ORDER,
                       fmt::format("simulation {} is running; connect again when it has finished", s.number()), "",
                       "hello", true),
             true);
      return;
    }
    if (!hello.client_name().empty()) {
      if (std::string problem = core::nameProblem(hello.client_name()); !problem.empty()) {
        s.send(out, id,
               makeError(v1::Error::INVALID_INPUT,
                         "hello.client_name = " + core::quotedLogText(hello.client_name(), 64) + ": " + problem, "",
                         "hello.client_name", true),
               true);
        return;
      }
    }
    if (!s.connections.empty() && hello.simulation() != s.group) {
      s.send(out, id,
             makeError(v1::Error::OUT_OF_ORDER,
                       fmt::format("simulation {} of {} is being assembled, held by client {}{}; this client "
                                   "asked for {}: connect again when it has finished",
                                   s.number(), core::quotedLogText(s.group),
                                   s.clientName(s.connections.begin()->first), s.assemblyTimeLeft(now),
                                   core::quotedLogText(hello.simulation())),
                       "", "hello.simulation", true),
             true);
      return;
    }
    if (s.connections.empty()) {
      s.group = hello.simulation();
      s.assembling_since = now;
    }
    s.connections[id].name = hello.client_name();
    if (!s.quiet_since) s.quiet_since = now;
    spdlog::info("client {} joined simulation {} ({})", s.clientName(id), s.number(), core::quotedLogText(s.group));
    Outgoing o;
    o.to = id;
    v1::Welcome& welcome = *o.message.mutable_welcome();
    welcome.set_protocol_version(v1::PROTOCOL_VERSION_CURRENT);
    welcome.set_server_name(s.options.server_name);
    welcome.set_simulation_number(s.number());
    out.push_back(std::move(o));
    if (s.compiler.expectedSetComplete()) s.compile(out, now);
  });
}

std::vector<Outgoing> CosimHost::received(ConnectionId from, const v1::ClientMessage& message,
                                                 SteadyClock::time_point now) {
  Impl& s = *impl_;
  s.record(v1::SessionEvent::RECEIVED, from, &message);
  return s.guarded([&](std::vector<Outgoing>& out) {
    const auto it = s.connections.find(from);
    if (it == s.connections.end() || it->second.said_bye) {
      s.send(out, from,
             makeError(v1::Error::OUT_OF_ORDER,
                       "this connection takes part in no simulation (no Hello, or its simulation has finished)", "",
                       "", true),
             true);
      return;
    }
    switch (message.message_case()) {
      case v1::ClientMessage::kHello:
        s.fault(out, from, makeError(v1::Error::OUT_OF_ORDER, "a second Hello on the same connection", "", "hello"));
        break;
      case v1::ClientMessage::kDeclare: s.onDeclare(out, from, message.declare(), now); break;
      case v1::ClientMessage::kData: s.onData(out, from, message.data(), now); break;
      case v1::ClientMessage::kBye: s.onBye(out, from, message.bye(), now); break;
      case v1::ClientMessage::kDeclarationsDone: s.onDeclarationsDone(out, from, now); break;
      case v1::ClientMessage::MESSAGE_NOT_SET:
        s.fault(out, from, makeError(v1::Error::BAD_FRAME, "an empty ClientMessage", "", "message"));
        break;
    }
  });
}

std::vector<Outgoing> CosimHost::disconnected(ConnectionId id, const std::string& why,
                                                     SteadyClock::time_point now) {
  Impl& s = *impl_;
  s.record(v1::SessionEvent::DISCONNECTED, id, nullptr, why);
  return s.guarded([&](std::vector<Outgoing>& out) { s.onDisconnect(out, id, why, now); });
}

std::vector<Outgoing> CosimHost::poll(SteadyClock::time_point now) {
  Impl& s = *impl_;
  if (!s.sim && s.quiet_since && !s.connections.empty() && s.usesQuietPeriod() &&
      now >= *s.quiet_since + seconds(s.options.quiet_period_s)) {
    return compileNow(now);
  }
  if (const std::optional<SteadyClock::time_point> deadline = s.assemblyDeadline(); deadline && now >= *deadline) {
    return expireAssemblyNow(now);
  }
  if (s.sim && s.waiting_since && !s.sim->scheduler().complete() && now >= *s.waiting_since + seconds(s.timeout())) {
    return expireWaitNow(now);
  }
  if (s.progress && now >= s.progress->next) s.logProgress(now);
  return {};
}

std::vector<Outgoing> CosimHost::compileNow(SteadyClock::time_point now) {
  Impl& s = *impl_;
  if (s.sim || s.connections.empty()) return {};
  s.record(v1::SessionEvent::COMPILE_NOW);
  return s.guarded([&](std::vector<Outgoing>& out) {
    spdlog::info("simulation {}: quiet period over, compiling {} declarations", s.number(),
                 s.compiler.declarations().size());
    s.compile(out, now);
  });
}

std::vector<Outgoing> CosimHost::expireAssemblyNow(SteadyClock::time_point /*now*/) {
  Impl& s = *impl_;
  if (s.sim || s.connections.empty()) return {};
  s.record(v1::SessionEvent::ASSEMBLY_TIMEOUT);
  return s.guarded([&](std::vector<Outgoing>& out) { s.expireAssembly(out); });
}

std::vector<Outgoing> CosimHost::expireWaitNow(SteadyClock::time_point /*now*/) {
  Impl& s = *impl_;
  if (!s.sim || s.sim->scheduler().complete()) return {};
  s.record(v1::SessionEvent::TIMEOUT);
  return s.guarded([&](std::vector<Outgoing>& out) { s.expire(out); });
}

std::optional<SteadyClock::time_point> CosimHost::nextDeadline() const {
  const Impl& s = *impl_;
  std::optional<SteadyClock::time_point> next;
  const auto consider = [&next](SteadyClock::time_point t) {
    if (!next || t < *next) next = t;
  };
  if (!s.sim && s.quiet_since && !s.connections.empty() && s.usesQuietPeriod()) {
    consider(*s.quiet_since + seconds(s.options.quiet_period_s));
  }
  if (const std::optional<SteadyClock::time_point> deadline = s.assemblyDeadline()) consider(*deadline);
  if (s.sim && s.waiting_since && !s.sim->scheduler().complete()) consider(*s.waiting_since + seconds(s.timeout()));
  if (s.progress) consider(s.progress->next);
  return next;
}

std::vector<Outgoing> CosimHost::shutdown(const std::string& reason, SteadyClock::time_point /*now*/) {
  Impl& s = *impl_;
  s.record(v1::SessionEvent::SHUTDOWN, 0, nullptr, reason);
  return s.guarded([&](std::vector<Outgoing>& out) {
    if (s.connections.empty() && !s.sim) return;
    const std::string cause = "server shutdown" + (reason.empty() ? std::string() : ": " + reason);
    for (const auto& [id, connection] : s.connections) {
      if (!connection.said_bye) {
        s.send(out, id, makeError(v1::Error::SERVER_SHUTDOWN, cause + " (outputs flushed, checkpoint written)", "", "", true));
      }
    }
    s.endSimulation(out, cause);
  });
}

bool CosimHost::simulationRunning() const { return impl_->sim != nullptr; }

CosimHost::Status CosimHost::status() const {
  const Impl& s = *impl_;
  Status status;
  status.number = s.number();
  status.running = s.sim != nullptr;
  status.group = s.group;
  for (const auto& [id, connection] : s.connections) status.clients.emplace_back(id, connection.name);
  status.assembly_deadline = s.assemblyDeadline();
  return status;
}

std::uint64_t CosimHost::simulationsFinished() const { return impl_->finished; }


const core::World* CosimHost::world() const {
  return impl_->sim ? &impl_->sim->compiled().scene->world : nullptr;
}

const CosimSimulation* CosimHost::simulation() const { return impl_->sim.get(); }

}  // namespace demlink::server
