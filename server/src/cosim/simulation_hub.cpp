/// Several simulations behind one network loop (contract in simulation_hub.hpp).
#include "demlink/server/cosim/simulation_hub.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <deque>
#include <limits>
#include <utility>

#include "demlink/core/base/log_text.hpp"
#include "demlink/server/cosim/cosim_compiler.hpp"
#include "demlink/server/cosim/session_recorder.hpp"
#include "demlink/server/cosim/simulation_worker.hpp"
#include "demlink/server/cosim/stepping_turns.hpp"

namespace demlink::server {

struct SimulationHub::Slot {
  std::uint64_t number = 0;
  std::shared_ptr<std::atomic<bool>> stop = std::make_shared<std::atomic<bool>>(false);
  std::unique_ptr<SimulationWorker> worker;
  CosimHost::Status status;  ///< as of the last report
  /// Hello.simulation of the clients routed here (set at routing, before the host knows).
  std::string group;
  std::uint64_t calls_posted = 0;
  /// Hellos posted and not reported yet (by their call's number): the slot is not idle
  /// while one is on its way, even though its last status shows no client; and if the
  /// simulation ends before its thread takes them, they are routed again.
  struct PendingHello {
    std::uint64_t call = 0;
    ConnectionId id = 0;
    v1::Hello hello;
  };
  std::deque<PendingHello> hellos_in_flight;
  /// Every posted call not reported yet, by its number, with its connection.
  std::deque<std::pair<std::uint64_t, ConnectionId>> calls_in_flight;

  [[nodiscard]] bool idle() const { return status.clients.empty() && hellos_in_flight.empty() && !status.running; }
  [[nodiscard]] bool assembling() const { return !status.running && !idle(); }
};

namespace {

Outgoing refusal(ConnectionId to, v1::Error error) {
  Outgoing o;
  o.to = to;
  *o.message.mutable_error() = std::move(error);
  o.close_after = true;
  return o;
}

}  // namespace

SimulationHub::SimulationHub(CosimOptions host, SimulationHubOptions options)
    : host_options_(std::move(host)), options_(options) {
  if (!host_options_.record_file.empty()) {
    // One record of one host's events in order: simulations one at a time.
    recorder_ = std::make_unique<SessionRecorder>(host_options_.record_file, host_options_);
    host_options_.record_file.clear();
    options_.max_open = 1;
  }
  options_.max_open = std::max<std::size_t>(options_.max_open, 1);
  turns_ = std::make_shared<SteppingTurns>(options_.max_stepping, options_.stepping_slice);
}

SimulationHub::~SimulationHub() {
  for (auto& [number, slot] : slots_) slot->stop->store(true);
  turns_->wakeAll();
  slots_.clear();  // each worker joins its thread
}

void SimulationHub::attachLoop(LoopPoster poster) {
  const std::lock_guard lock(post_mutex_);
  post_ = std::move(poster);
}

SimulationHub::Slot& SimulationHub::open() {
  auto slot = std::make_unique<Slot>();
  slot->number = next_number_++;
  ++opened_;
  CosimOptions options = host_options_;
  host_options_.restore_file.clear();  // the first simulation only
  options.first_simulation_number = slot->number;
  // A stop (shutdown) or another simulation's turn ends an interval at a step boundary;
  // on LIGGGHTS under MPI every rank stops at that step (CosimOptions::stop_consensus).
  options.stop_stepping = slot->stop;
  options.turns = turns_;
  if (recorder_) {
    options.on_event = [this, forward = host_options_.on_event](const v1::SessionEvent& event) {
      if (forward) forward(event);
      const std::lock_guard lock(recorder_mutex_);
      if (!recorder_) return;
      try {
        recorder_->record(event);
      } catch (const std::exception& error) {
        spdlog::error("session recorder: {}; recording stopped", error.what());
        recorder_.reset();
      }
    };
  }
  const std::uint64_t number = slot->number;
  auto report = [this, number](std::vector<Outgoing> out, CosimHost::Status status, bool ended,
                               std::uint64_t callsDone) {
    LoopPoster poster;
    {
      const std::lock_guard lock(post_mutex_);
      poster = post_;
    }
    if (!poster) return;  // the transport has gone: nobody to send to
    poster([this, number, out = std::move(out), status = std::move(status), ended, callsDone]() mutable {
      return onReport(number, std::move(out), std::move(status), ended, callsDone);
    });
  };
  slot->status.number = number;
  slot->worker =
      std::make_unique<SimulationWorker>(std::make_unique<CosimHost>(std::move(options)), report, options_.spin_wait);
  Slot& opened = *slot;
  slots_.emplace(number, std::move(slot));
  return opened;
}

void SimulationHub::post(Slot& slot, ConnectionId id, std::function<std::vector<Outgoing>(CosimHost&)> call) {
  ++slot.calls_posted;
  slot.calls_in_flight.emplace_back(slot.calls_posted, id);
  ++pending_calls_[id];
  slot.worker->post(std::move(call));
}

void SimulationHub::settle(Slot& slot, std::uint64_t callsDone) {
  while (!slot.calls_in_flight.empty() && slot.calls_in_flight.front().first <= callsDone) {
    const auto found = pending_calls_.find(slot.calls_in_flight.front().second);
    if (found != pending_calls_.end() && --found->second == 0) pending_calls_.erase(found);
    slot.calls_in_flight.pop_front();
  }
}

std::size_t SimulationHub::pendingCalls(ConnectionId id) const {
  const auto found = pending_calls_.find(id);
  return found == pending_calls_.end() ? 0 : found->second;
}

std::string SimulationHub::holders(SteadyClock::time_point now) const {
  std::string text;
  for (const auto& [number, slot] : slots_) {
    if (slot->idle()) continue;
    const CosimHost::Status& s = slot->status;
    std::string clients;
    std::size_t shown = 0;
    for (const auto& [id, name] : s.clients) {
      if (++shown > 3) {
        clients += fmt::format(" and {} more", s.clients.size() - 3);
        break;
      }
      clients += fmt::format("{}{} (connection {})", clients.empty() ? "" : ", ",
                             name.empty() ? std::string("(unnamed)") : core::quotedLogText(name, 64), id);
    }
    if (clients.empty()) clients = "a client still being welcomed";
    std::string state = s.running ? "is running" : "is being assembled";
    if (!s.running && s.assembly_deadline) {
      const double left = std::chrono::duration<double>(*s.assembly_deadline - now).count();
      state += fmt::format(" (its assembly times out in {:.1f} s)", std::max(left, 0.0));
    }
    text += fmt::format("{}simulation {} of {} {}, held by {}", text.empty() ? "" : "; ", number,
                        core::quotedLogText(slot->group, 64), state, clients);
  }
  return text;
}

SimulationHub::Slot* SimulationHub::route(const v1::Hello& hello, SteadyClock::time_point now,
                                          std::optional<v1::Error>& refused) {
  const std::string& group = hello.simulation();
  for (auto& [number, slot] : slots_) {
    if (slot->assembling() && slot->group == group) return slot.get();
  }
  for (auto& [number, slot] : slots_) {
    if (slot->status.running && slot->group == group) {
      refused = makeError(v1::Error::OUT_OF_ORDER,
                          fmt::format("simulation {} of {} is running; connect again when it has finished", number,
                                      core::quotedLogText(group, 64)),
                          "", "hello.simulation", true);
      return nullptr;
    }
  }
  for (auto& [number, slot] : slots_) {
    if (slot->idle()) return slot.get();
  }
  if (options_.max_total > 0 && opened_ >= options_.max_total) {
    refused = makeError(v1::Error::SERVER_BUSY,
                        fmt::format("this server runs {} simulation(s) in all and has opened them: {}",
                                    options_.max_total, holders(now)),
                        "", "hello.simulation", true);
    return nullptr;
  }
  if (slots_.size() >= options_.max_open) {
    refused = makeError(v1::Error::SERVER_BUSY,
                        fmt::format("{} simulation(s) are open, the most this server holds at once "
                                    "(--max-open-simulations); connect again when one has finished: {}",
                                    slots_.size(), holders(now)),
                        "", "hello.simulation", true);
    return nullptr;
  }
  return &open();
}

std::vector<Outgoing> SimulationHub::connected(ConnectionId id, const v1::Hello& hello,
                                               SteadyClock::time_point now) {
  if (stopping_) return {};
  std::optional<v1::Error> refused;
  Slot* slot = route(hello, now, refused);
  if (slot == nullptr) {
    spdlog::warn("connection {}: {}", id, core::logText(refused->message(), 1000));
    return {refusal(id, std::move(*refused))};
  }
  if (slot->idle()) {
    // Reused: its last clients left (which may have cut an interval short); it starts afresh.
    slot->group = hello.simulation();
    slot->stop->store(false);
  }
  members_[id] = slot->number;
  post(*slot, id, [id, hello, now](CosimHost& host) { return host.connected(id, hello, now); });
  slot->hellos_in_flight.push_back({slot->calls_posted, id, hello});
  return {};
}

std::vector<Outgoing> SimulationHub::received(ConnectionId from, const v1::ClientMessage& message,
                                              SteadyClock::time_point now) {
  const auto member = members_.find(from);
  const auto slot = member == members_.end() ? slots_.end() : slots_.find(member->second);
  if (slot == slots_.end()) {
    return {refusal(from, makeError(v1::Error::OUT_OF_ORDER,
                                    "this connection takes part in no simulation (no Hello, or its simulation has "
                                    "finished)",
                                    "", "", true))};
  }
  post(*slot->second, from, [from, message, now](CosimHost& host) { return host.received(from, message, now); });
  return {};
}

std::vector<Outgoing> SimulationHub::disconnected(ConnectionId id, const std::string& why,
                                                  SteadyClock::time_point now) {
  const auto member = members_.find(id);
  if (member == members_.end()) return {};
  const std::uint64_t number = member->second;
  const auto slot = slots_.find(number);
  members_.erase(member);
  if (slot == slots_.end()) return {};
  const bool nobodyLeft =
      std::none_of(members_.begin(), members_.end(), [number](const auto& entry) { return entry.second == number; });
  if (nobodyLeft && slot->second->status.running) {
    // Nobody is left to answer: an interval in progress, however long, is cut short, and
    // the host ends the simulation on this disconnect (outputs flushed).
    slot->second->stop->store(true);
    turns_->wakeAll();
  }
  post(*slot->second, id, [id, why, now](CosimHost& host) { return host.disconnected(id, why, now); });
  return {};
}

std::vector<Outgoing> SimulationHub::onReport(std::uint64_t number, std::vector<Outgoing> out,
                                              CosimHost::Status status, bool ended, std::uint64_t callsDone) {
  const auto found = slots_.find(number);
  if (found == slots_.end()) return out;  // reaped or shut down already
  Slot& slot = *found->second;
  settle(slot, callsDone);
  while (!slot.hellos_in_flight.empty() && slot.hellos_in_flight.front().call <= callsDone) {
    slot.hellos_in_flight.pop_front();
  }
  if (!status.clients.empty()) slot.group = status.group;
  slot.status = std::move(status);
  if (ended) {
    ++finished_;
    std::deque<Slot::PendingHello> unanswered = std::move(slot.hellos_in_flight);
    settle(slot, std::numeric_limits<std::uint64_t>::max());  // the calls it dropped
    std::erase_if(members_, [number](const auto& entry) { return entry.second == number; });
    slots_.erase(found);  // joins the worker, whose thread returns after this report
    // Hellos that reached the simulation after it had ended: they go where a new Hello would.
    for (const Slot::PendingHello& pending : unanswered) {
      for (Outgoing& o : connected(pending.id, pending.hello, SteadyClock::now())) out.push_back(std::move(o));
    }
  }
  return out;
}

std::vector<Outgoing> SimulationHub::shutdown(const std::string& reason, SteadyClock::time_point now) {
  stopping_ = true;
  for (auto& [number, slot] : slots_) slot->stop->store(true);
  turns_->wakeAll();
  std::vector<Outgoing> out;
  for (auto& [number, slot] : slots_) {
    const bool active = !slot->idle();
    std::vector<Outgoing> last =
        slot->worker->finish([&reason, now](CosimHost& host) { return host.shutdown(reason, now); });
    if (active) ++finished_;
    for (Outgoing& o : last) out.push_back(std::move(o));
  }
  slots_.clear();
  members_.clear();
  pending_calls_.clear();
  return out;
}

}  // namespace demlink::server
