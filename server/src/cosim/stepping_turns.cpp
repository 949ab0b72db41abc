/// Turns for stepping simulations (contract in stepping_turns.hpp).
#include "demlink/server/cosim/stepping_turns.hpp"

#include <algorithm>

namespace demlink::server {
namespace {

bool stopped(const std::atomic<bool>* stop) { return stop != nullptr && stop->load(std::memory_order_relaxed); }

/// A waiter rechecks its stop flag this often even if nobody wakes it (the flag is set by
/// a signal handler's loop, which wakes the turns too; this is the bound if it did not).
constexpr std::chrono::milliseconds kStopPoll{20};

}  // namespace

SteppingTurns::SteppingTurns(std::size_t concurrent, Clock::duration slice)
    : concurrent_(std::max<std::size_t>(concurrent, 1)), slice_(slice) {}

bool SteppingTurns::acquire(const std::atomic<bool>* stop) {
  std::unique_lock lock(mutex_);
  const std::uint64_t ticket = next_ticket_++;
  queue_.push_back(ticket);
  for (;;) {
    if (stopped(stop)) {
      queue_.erase(std::find(queue_.begin(), queue_.end(), ticket));
      changed_.notify_all();
      return false;
    }
    if (queue_.front() == ticket && stepping_ < concurrent_) {
      queue_.pop_front();
      ++stepping_;
      changed_.notify_all();  // the next in the queue may have a free turn too
      return true;
    }
    changed_.wait_for(lock, kStopPoll);
  }
}

void SteppingTurns::release() {
  {
    const std::lock_guard lock(mutex_);
    --stepping_;
  }
  changed_.notify_all();
}

bool SteppingTurns::othersWait() {
  const std::lock_guard lock(mutex_);
  return !queue_.empty();
}

void SteppingTurns::wakeAll() { changed_.notify_all(); }

SteppingTurns::Turn::Turn(SteppingTurns& turns, const std::atomic<bool>* stop) : turns_(turns), stop_(stop) {
  held_ = turns_.acquire(stop_);
  since_ = Clock::now();
}

SteppingTurns::Turn::~Turn() {
  if (held_) turns_.release();
}

bool SteppingTurns::Turn::mayStep() {
  if (stopped(stop_)) return false;
  if (!held_) return false;
  const Clock::time_point now = Clock::now();
  if (now - since_ < turns_.slice_) return true;
  if (!turns_.othersWait()) {
    since_ = now;  // nobody to give way to: the next look after another slice
    return true;
  }
  turns_.release();
  held_ = turns_.acquire(stop_);
  since_ = Clock::now();
  return held_;
}

}  // namespace demlink::server
