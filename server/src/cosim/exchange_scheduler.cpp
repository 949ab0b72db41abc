/// Sample-grid bookkeeping (contract in exchange_scheduler.hpp).
///
/// A handful of components per simulation: linear scans over a vector are simpler than
/// any index and cost nothing next to a world step.
#include "demlink/server/cosim/exchange_scheduler.hpp"

#include <algorithm>
#include <stdexcept>

namespace demlink::server {

void ExchangeScheduler::add(std::size_t index, std::uint64_t intervalSteps) {
  if (intervalSteps == 0) throw std::invalid_argument("ExchangeScheduler::add: interval of 0 steps");
  if (find(index) != nullptr) throw std::invalid_argument("ExchangeScheduler::add: component added twice");
  entries_.push_back({index, intervalSteps, true, false});
}

void ExchangeScheduler::startAt(std::uint64_t step) {
  const bool untouched = step_ == 0 && std::none_of(entries_.begin(), entries_.end(), [](const Entry& e) {
    return e.received || !e.active;
  });
  if (!untouched) throw std::invalid_argument("ExchangeScheduler::startAt: the grid has already started");
  for (const Entry& e : entries_) {
    if (step % e.interval != 0) throw std::invalid_argument("ExchangeScheduler::startAt: a component is not due there");
  }
  step_ = step;
}

void ExchangeScheduler::retire(std::size_t index) {
  for (Entry& e : entries_) {
    if (e.index == index) e.active = false;
  }
}

const ExchangeScheduler::Entry* ExchangeScheduler::find(std::size_t index) const {
  for (const Entry& e : entries_) {
    if (e.index == index) return &e;
  }
  return nullptr;
}

std::uint64_t ExchangeScheduler::interval(std::size_t index) const {
  const Entry* e = find(index);
  return e != nullptr ? e->interval : 0;
}

std::optional<std::uint64_t> ExchangeScheduler::expectedStep(std::size_t index) const {
  const Entry* e = find(index);
  if (e == nullptr || !e->active) return std::nullopt;
  if (dueAt(*e, step_) && !e->received) return step_;
  return (step_ / e->interval + 1) * e->interval;
}

ExchangeScheduler::Offer ExchangeScheduler::offer(std::size_t index, std::uint64_t step) {
  Entry* entry = nullptr;
  for (Entry& e : entries_) {
    if (e.index == index) entry = &e;
  }
  if (entry == nullptr || !entry->active) return Offer::NotExchanged;
  if (dueAt(*entry, step_) && step == step_) {
    if (entry->received) return Offer::AlreadyReceived;
    entry->received = true;
    return Offer::Accepted;
  }
  return step == *expectedStep(index) ? Offer::NotDue : Offer::WrongStep;
}

std::vector<std::size_t> ExchangeScheduler::missing() const {
  std::vector<std::size_t> out;
  for (const Entry& e : entries_) {
    if (dueAt(e, step_) && !e.received) out.push_back(e.index);
  }
  return out;
}

bool ExchangeScheduler::anyActive() const {
  return std::any_of(entries_.begin(), entries_.end(), [](const Entry& e) { return e.active; });
}

std::optional<std::uint64_t> ExchangeScheduler::nextStop(std::uint64_t endStep) const {
  std::optional<std::uint64_t> next;
  for (const Entry& e : entries_) {
    if (!e.active) continue;
    const std::uint64_t due = (step_ / e.interval + 1) * e.interval;
    if (!next || due < *next) next = due;
  }
  if (endStep > 0) {
    if (step_ >= endStep) return std::nullopt;
    if (!next || *next > endStep) next = endStep;
  }
  return next;
}

std::vector<std::size_t> ExchangeScheduler::advanceTo(std::uint64_t step) {
  if (step <= step_) throw std::invalid_argument("ExchangeScheduler::advanceTo: step does not advance");
  step_ = step;
  std::vector<std::size_t> ended;
  for (Entry& e : entries_) {
    e.received = false;
    if (dueAt(e, step_)) ended.push_back(e.index);
  }
  return ended;
}

}  // namespace demlink::server
