/// Session bookkeeping. Each component tracks the step of its next package and whether an
/// answer is outstanding; an answer must arrive for exactly (sent step + interval), so a
/// server that breaks the schedule is reported instead of silently shifting the outputs.
#include "demlink/client/session.hpp"

#include <google/protobuf/util/message_differencer.h>

#include <algorithm>
#include <limits>

#include "demlink/v1/protocol.pb.h"

namespace demlink::client {

Session::Session(Connection& connection)
    : connection_(connection), compiled_(new v1::Compiled()), finished_(new v1::Finished()) {}

double Session::timeStep() const { return compiled_->time_step(); }
std::uint64_t Session::endStep() const { return compiled_->end_step(); }
const v1::CompileReport& Session::report() const { return compiled_->report(); }
std::string Session::reportText() const { return compiled_->report().text(); }
std::string Session::finishedReason() const { return finished_->reason(); }

Component* Session::find(const std::string& name) {
  for (auto& c : components_) {
    if (c->name() == name) return c.get();
  }
  return nullptr;
}

void Session::requireNotCompiled(const char* what) const {
  if (compiled_flag_) throw StateError(std::string("Session::") + what + ": the simulation is already compiled");
}

void Session::requireCompiled(const char* what) const {
  if (!compiled_flag_) throw StateError(std::string("Session::") + what + ": call waitCompiled() first");
  if (finished_flag_) throw StateError(std::string("Session::") + what + ": the simulation has finished");
}

void Session::declare() {
  requireNotCompiled("declare");
  for (auto& c : components_) {
    if (c->declared_) continue;
    c->prepareDeclaration();
    v1::ClientMessage message;
    *message.mutable_declare()->mutable_component() = *c->declaration_;
    connection_.send(message);
    c->declared_ = true;
  }
}

Component& Session::declareOnce(std::unique_ptr<Component> component, std::size_t& index) {
  component->prepareDeclaration();
  for (std::size_t i = 0; i < components_.size(); ++i) {
    Component& existing = *components_[i];
    if (existing.name() != component->name()) continue;
    if (!google::protobuf::util::MessageDifferencer::Equals(*existing.declaration_, *component->declaration_)) {
      throw StateError("component '" + component->name() +
                       "' is already declared on this connection with a different declaration");
    }
    index = i;
    return existing;
  }
  requireNotCompiled("declare");
  components_.push_back(std::move(component));
  declare();
  index = components_.size() - 1;
  return *components_.back();
}

void Session::declarationsDone() {
  if (done_sent_ || compiled_flag_ || finished_flag_) return;
  declare();
  v1::ClientMessage message;
  message.mutable_declarations_done();
  connection_.send(message);
  done_sent_ = true;
}

const v1::Compiled& Session::waitCompiled() {
  while (!compiled_flag_) {
    if (finished_flag_) {
      throw StateError("the simulation ended before it was compiled: " + finished_->reason());
    }
    pump();
  }
  return *compiled_;
}

void Session::applyCompiled(const v1::Compiled& compiled) {
  if (compiled_flag_) throw StateError("the server sent Compiled twice");
  for (const auto& entry : compiled.components()) {
    Component* c = find(entry.name());
    if (c == nullptr) throw StateError("Compiled lists component '" + entry.name() + "' that this session did not declare");
    c->compiled_ = true;
    c->id_ = entry.id();
    c->interval_steps_ = entry.interval_steps();
    c->next_send_step_ = compiled.start_step();  // 0, or a restored checkpoint's step
    c->awaiting_ = false;
  }
  for (const auto& c : components_) {
    if (!c->compiled_) throw StateError("Compiled does not list declared component '" + c->name() + "'");
  }
  for (const auto& initial : compiled.initial_outputs()) {
    for (auto& c : components_) {
      if (c->id_ == initial.component_id()) *c->outputs_ = initial;
    }
  }
  *compiled_ = compiled;
  compiled_flag_ = true;
  current_ = compiled.start_step();
}

Component* Session::applyData(const v1::DataPackage& package) {
  Component* target = nullptr;
  for (auto& c : components_) {
    if (c->compiled_ && c->id_ == package.component_id()) target = c.get();
  }
  if (target == nullptr) {
    throw StateError("the server answered component id " + std::to_string(package.component_id()) +
                     ", which this session does not own");
  }
  const std::uint64_t expected = target->next_send_step_ + target->interval_steps_;
  if (!target->awaiting_ || package.step() != expected) {
    throw StateError("unexpected answer for '" + target->name() + "' at step " + std::to_string(package.step()) +
                     (target->awaiting_ ? " (expected step " + std::to_string(expected) + ")" : " (no package sent)"));
  }
  *target->outputs_ = package;
  target->awaiting_ = false;
  target->next_send_step_ = package.step();  // due again where its interval ended
  return target;
}

Component* Session::pump() {
  v1::ServerMessage message;
  try {
    message = connection_.receive();
  } catch (const ServerError&) {
    // A fatal error ends the simulation: keep its Finished (where the results are).
    if (connection_.finishedAfterError()) {
      *finished_ = *connection_.finishedAfterError();
      finished_flag_ = true;
    }
    throw;
  }
  switch (message.message_case()) {
    case v1::ServerMessage::kCompiled:
      applyCompiled(message.compiled());
      return nullptr;
    case v1::ServerMessage::kData:
      return applyData(message.data());
    case v1::ServerMessage::kFinished:
      *finished_ = message.finished();
      finished_flag_ = true;
      connection_.close();  // the server ends the connection after Finished; hang up at once
      return nullptr;
    default:
      throw StateError("unexpected server message (case " + std::to_string(static_cast<int>(message.message_case())) +
                       ")");
  }
}

std::vector<Component*> Session::due() const {
  std::vector<Component*> out;
  for (const auto& c : components_) {
    if (c->exchanged() && !c->awaiting_ && c->next_send_step_ == current_) out.push_back(c.get());
  }
  return out;
}

bool Session::exchange() {
  if (finished_flag_) return false;
  requireCompiled("exchange");
  if (endStep() > 0 && current_ >= endStep()) {
    // Nothing is due after the last step; the server ends the simulation there.
    waitFinished();
    return false;
  }
  for (Component* c : due()) send(*c);
  std::uint64_t target = std::numeric_limits<std::uint64_t>::max();
  for (const auto& c : components_) {
    if (c->awaiting_) target = std::min(target, c->next_send_step_ + c->interval_steps_);
  }
  if (target == std::numeric_limits<std::uint64_t>::max()) {
    throw StateError("Session::exchange: no component of this session is exchanged (all intervals are 0)");
  }
  auto outstandingAtTarget = [&] {
    return std::any_of(components_.begin(), components_.end(), [&](const auto& c) {
      return c->awaiting_ && c->next_send_step_ + c->interval_steps_ == target;
    });
  };
  while (outstandingAtTarget()) {
    pump();
    if (finished_flag_) return false;
  }
  current_ = target;
  return true;
}

void Session::send(Component& component) {
  requireCompiled("send");
  if (!component.exchanged()) throw StateError("component '" + component.name() + "' is not exchanged (interval 0)");
  if (component.awaiting_) {
    throw StateError("component '" + component.name() + "': the answer to its previous package has not arrived");
  }
  v1::ClientMessage message;
  v1::DataPackage& package = *message.mutable_data();
  package.set_component_id(component.id_);
  package.set_step(component.next_send_step_);
  component.writeInputs(package);
  connection_.send(message);
  component.inputsSent();
  component.awaiting_ = true;
}

bool Session::receive(Component& component) {
  requireCompiled("receive");
  if (!component.awaiting_) throw StateError("component '" + component.name() + "' has no package in flight");
  while (component.awaiting_) {
    pump();
    if (finished_flag_) return false;
  }
  current_ = std::max(current_, component.outputStep());
  return true;
}

Component* Session::receiveAny() {
  requireCompiled("receiveAny");
  for (;;) {
    Component* c = pump();
    if (finished_flag_) return nullptr;
    if (c != nullptr) {
      current_ = std::max(current_, c->outputStep());
      return c;
    }
  }
}

void Session::sendBye(const std::string& reason) {
  if (bye_sent_ || finished_flag_) return;
  v1::ClientMessage message;
  message.mutable_bye()->set_reason(reason);
  connection_.send(message);
  bye_sent_ = true;
}

const v1::Finished& Session::waitFinished() {
  while (!finished_flag_) pump();
  return *finished_;
}

const v1::Finished& Session::finish(const std::string& reason) {
  if (finished_flag_) return *finished_;
  sendBye(reason);
  return waitFinished();
}

}  // namespace demlink::client
