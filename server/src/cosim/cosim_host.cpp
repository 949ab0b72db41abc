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

#include <map>

#include "demlink/server/cosim/cosim_compiler.hpp"
#include "demlink/server/cosim/cosim_simulation.hpp"
#include "demlink/server/cosim/session_recorder.hpp"
#include "demlink/server/run/output_directory.hpp"

namespace demlink::server {
namespace {

struct Connection {
  std::string name;
  bool declared = false;  ///< declared at least one component
  bool said_bye = false;  ///< got its Finished already
};

SteadyClock::duration seconds(double s) {
  return std::chrono::duration_cast<SteadyClock::duration>(std::chrono::duration<double>(s));
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
  std::uint64_t finished = 0;
  std::optional<SteadyClock::time_point> quiet_since;
  std::optional<SteadyClock::time_point> waiting_since;
  std::unique_ptr<SessionRecorder> recorder;
  std::filesystem::path last_directory;

  // --- recording -----------------------------------------------------------------
  void record(v1::SessionEvent::Kind kind, ConnectionId id = 0, const v1::ClientMessage* message = nullptr,
              const std::string& text = {}) {
    if (!recorder) return;
    v1::SessionEvent event;
    event.set_kind(kind);
    event.set_connection(id);
    if (message != nullptr) *event.mutable_message() = *message;
    event.set_text(text);
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
    const std::string name = it != connections.end() && !it->second.name.empty() ? it->second.name : "(unnamed)";
    return fmt::format("\"{}\" (connection {})", name, id);
  }

  [[nodiscard]] std::uint64_t number() const { return finished + 1; }

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
      spdlog::info("simulation {} ended at step {} (t = {:.6g} s): {}; output in {}", number(),
                   sim->scheduler().currentStep(),
                   static_cast<double>(sim->scheduler().currentStep()) * sim->compiled().time_step, reason,
                   sim->outputDirectory().string());
    } else {
      spdlog::info("simulation {} ended before it was compiled: {}", number(), reason);
    }
    for (const auto& [id, connection] : connections) {
      if (!connection.said_bye) sendFinished(out, id, reason);
    }
    connections.clear();
    sim.reset();
    compiler.reset();
    quiet_since.reset();
    waiting_since.reset();
    ++finished;
  }

  /// A client broke the protocol or sent invalid input: fatal Error to it, the cause to
  /// the others (`othersCode`), then the simulation ends.
  void fault(std::vector<Outgoing>& out, ConnectionId offender, v1::Error error,
             v1::Error::Code othersCode = v1::Error::PEER_DISCONNECTED) {
    error.set_fatal(true);
    spdlog::warn("simulation {}: client {}: {} ({}{}{})", number(), clientName(offender), error.message(),
                 v1::Error::Code_Name(error.code()), error.field().empty() ? "" : ", field ", error.field());
    send(out, offender, error);
    const std::string cause = "client " + clientName(offender) + ": " + error.message();
    for (const auto& [id, connection] : connections) {
      if (id == offender || connection.said_bye) continue;
      send(out, id, makeError(othersCode, "the simulation ended: " + cause, error.component(), error.field(), true));
    }
    endSimulation(out, cause);
  }

  void compile(std::vector<Outgoing>& out, SteadyClock::time_point now) {
    const SteadyClock::time_point workStart = SteadyClock::now();
    CompiledSimulation compiled;
    try {
      compiled = compiler.compile(options.scene_directory);
    } catch (const CompileFailure& failure) {
      spdlog::error("simulation {}: compile failed: {}", number(), failure.error.message());
      for (const auto& [id, connection] : connections) send(out, id, failure.error);
      endSimulation(out, "compile failed: " + failure.error.message());
      return;
    }
    std::filesystem::path directory;
    try {
      // Never an earlier simulation's folder, unless told to overwrite (output_directory.hpp).
      compiled.scene->run.overwrite = options.overwrite;
      const std::uint64_t folder =
          options.overwrite ? number() : claimSimulationDirectory(options.output_root, number());
      directory = simulationDirectory(options.output_root, folder);
      sim = std::make_unique<CosimSimulation>(std::move(compiled), directory);
    } catch (const std::exception& error) {
      const v1::Error e = makeError(v1::Error::INTERNAL, std::string("cannot start the simulation: ") + error.what(),
                                    "", "", true);
      for (const auto& [id, connection] : connections) send(out, id, e);
      endSimulation(out, e.message());
      return;
    }
    last_directory = directory;
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
    if (sim) waiting_since = now + (SteadyClock::now() - workStart);
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

  // --- events --------------------------------------------------------------------
  void onDeclare(std::vector<Outgoing>& out, ConnectionId from, const v1::Declare& declare,
                 SteadyClock::time_point now) {
    if (sim) {
      fault(out, from,
            makeError(v1::Error::OUT_OF_ORDER,
                      "Declare of \"" + declare.component().name() + "\" after Compiled: the simulation is running",
                      declare.component().name(), "declare"));
      return;
    }
    if (std::optional<v1::Error> refused = compiler.declare(from, declare.component())) {
      spdlog::warn("client {}: declaration refused: {}", clientName(from), refused->message());
      send(out, from, *refused);
      return;
    }
    connections[from].declared = true;
    quiet_since = now;
    spdlog::info("client {} declared \"{}\"", clientName(from), declare.component().name());
    if (compiler.expectedSetComplete()) compile(out, now);
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
    if (sim->scheduler().complete()) run(out, now);
  }

  void onBye(std::vector<Outgoing>& out, ConnectionId from, const v1::Bye& bye, SteadyClock::time_point now) {
    spdlog::info("client {} said Bye{}{}", clientName(from), bye.reason().empty() ? "" : ": ", bye.reason());
    if (!sim) {
      compiler.withdraw(from);
      sendFinished(out, from, "said Bye before the simulation was compiled");
      connections.erase(from);
      if (connections.empty()) {
        compiler.reset();
        quiet_since.reset();
      } else if (compiler.expectedSetComplete()) {
        compile(out, now);
      }
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
    if (sim->scheduler().complete()) run(out, now);
  }

  void onDisconnect(std::vector<Outgoing>& out, ConnectionId id, const std::string& why) {
    const auto it = connections.find(id);
    if (it == connections.end()) return;
    const Connection connection = it->second;
    if (!sim) {
      spdlog::info("client {} left before the compile ({})", clientName(id), why);
      compiler.withdraw(id);
      connections.erase(it);
      if (connections.empty()) {
        compiler.reset();
        quiet_since.reset();
      }
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
    std::string names;
    for (const std::size_t index : missing) {
      const CosimComponent& c = sim->components()[index];
      names += (names.empty() ? "" : ", ") + ("\"" + c.name + "\" of client " + clientName(*c.owner));
    }
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

  template <class Body>
  std::vector<Outgoing> guarded(Body body) {
    std::vector<Outgoing> out;
    try {
      body(out);
    } catch (const std::exception& error) {
      // A watchdog stop is the world refusing to go on, not a bug: its own code, the check as the field.
      const auto* fault = dynamic_cast<const core::SimulationFault*>(&error);
      spdlog::error("simulation {}: {}: {}", number(), fault != nullptr ? "stopped" : "internal error", error.what());
      const v1::Error e =
          fault != nullptr
              ? makeError(v1::Error::SIMULATION_FAULT, error.what(), "", "watchdog." + fault->check(), true)
              : makeError(v1::Error::INTERNAL, std::string("internal error: ") + error.what(), "", "", true);
      for (const auto& [id, connection] : connections) {
        if (!connection.said_bye) send(out, id, e);
      }
      try {
        endSimulation(out, e.message());
      } catch (const std::exception& again) {
        spdlog::error("ending the simulation failed too: {}", again.what());
        connections.clear();
        sim.reset();
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
    s.connections[id].name = hello.client_name();
    if (!s.quiet_since) s.quiet_since = now;
    spdlog::info("client {} joined simulation {}", s.clientName(id), s.number());
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
      case v1::ClientMessage::MESSAGE_NOT_SET:
        s.fault(out, from, makeError(v1::Error::BAD_FRAME, "an empty ClientMessage", "", "message"));
        break;
    }
  });
}

std::vector<Outgoing> CosimHost::disconnected(ConnectionId id, const std::string& why,
                                                     SteadyClock::time_point /*now*/) {
  Impl& s = *impl_;
  s.record(v1::SessionEvent::DISCONNECTED, id, nullptr, why);
  return s.guarded([&](std::vector<Outgoing>& out) { s.onDisconnect(out, id, why); });
}

std::vector<Outgoing> CosimHost::poll(SteadyClock::time_point now) {
  Impl& s = *impl_;
  if (!s.sim && s.quiet_since && !s.connections.empty() && s.compiler.usesQuietPeriod() &&
      now >= *s.quiet_since + seconds(s.options.quiet_period_s)) {
    return compileNow(now);
  }
  if (s.sim && s.waiting_since && !s.sim->scheduler().complete() && now >= *s.waiting_since + seconds(s.timeout())) {
    return expireWaitNow(now);
  }
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

std::vector<Outgoing> CosimHost::expireWaitNow(SteadyClock::time_point /*now*/) {
  Impl& s = *impl_;
  if (!s.sim || s.sim->scheduler().complete()) return {};
  s.record(v1::SessionEvent::TIMEOUT);
  return s.guarded([&](std::vector<Outgoing>& out) { s.expire(out); });
}

std::optional<SteadyClock::time_point> CosimHost::nextDeadline() const {
  const Impl& s = *impl_;
  if (!s.sim && s.quiet_since && !s.connections.empty() && s.compiler.usesQuietPeriod()) {
    return *s.quiet_since + seconds(s.options.quiet_period_s);
  }
  if (s.sim && s.waiting_since && !s.sim->scheduler().complete()) return *s.waiting_since + seconds(s.timeout());
  return std::nullopt;
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

std::uint64_t CosimHost::simulationsFinished() const { return impl_->finished; }

std::filesystem::path CosimHost::lastOutputDirectory() const { return impl_->last_directory; }

const core::World* CosimHost::world() const {
  return impl_->sim ? &impl_->sim->compiled().scene->world : nullptr;
}

const CosimSimulation* CosimHost::simulation() const { return impl_->sim.get(); }

}  // namespace demlink::server
