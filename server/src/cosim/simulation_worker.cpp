/// One simulation's thread (contract in simulation_worker.hpp).
#include "demlink/server/cosim/simulation_worker.hpp"

#include <spdlog/spdlog.h>

#include "demlink/core/parallel/spin_history.hpp"

#include <exception>
#include <optional>
#include <utility>

namespace demlink::server {

SimulationWorker::SimulationWorker(std::unique_ptr<CosimHost> host, Report report, std::chrono::nanoseconds spinWait)
    : host_(std::move(host)), report_(std::move(report)), spin_wait_(spinWait) {
  thread_ = std::thread([this] { loop(); });
}

SimulationWorker::~SimulationWorker() {
  {
    const std::lock_guard lock(mutex_);
    quit_ = true;
    queue_.clear();
    pending_.store(1, std::memory_order_release);
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void SimulationWorker::post(Work work) {
  {
    const std::lock_guard lock(mutex_);
    if (quit_ || ended_) return;
    queue_.push_back(std::move(work));
    pending_.store(queue_.size(), std::memory_order_release);
  }
  wake_.notify_all();
}

std::vector<Outgoing> SimulationWorker::finish(const Work& last) {
  {
    const std::lock_guard lock(mutex_);
    quit_ = true;
    queue_.clear();
    pending_.store(1, std::memory_order_release);
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  // The thread has returned: the host is this thread's now.
  if (ended_) return {};
  try {
    return last(*host_);
  } catch (const std::exception& error) {
    spdlog::error("simulation {}: ending it failed: {}", host_->status().number, error.what());
    return {};
  }
}

void SimulationWorker::loop() {
  core::SpinHistory history;
  for (;;) {
    std::optional<Work> work;
    bool timer = false;
    // A call that comes within the budget is taken without blocking (the header says why);
    // a host timer due before then is left to the blocking wait below.
    const std::optional<SteadyClock::time_point> due = host_->nextDeadline();
    const bool spun = pending_.load(std::memory_order_acquire) == 0 &&
                      (!due || *due > SteadyClock::now() + spin_wait_) &&
                      core::spinFor(history, core::SpinGate::Party::kExchange, spin_wait_,
                                    [this] { return pending_.load(std::memory_order_acquire) > 0; });
    {
      std::unique_lock lock(mutex_);
      const std::optional<SteadyClock::time_point> deadline = host_->nextDeadline();
      const auto ready = [this] { return quit_ || !queue_.empty(); };
      if (deadline) {
        timer = !wake_.wait_until(lock, *deadline, ready);
      } else {
        wake_.wait(lock, ready);
      }
      if (quit_) return;
      if (!timer) {
        work = std::move(queue_.front());
        queue_.pop_front();
        pending_.store(queue_.size(), std::memory_order_release);
      }
    }
    if (work && !spun && spin_wait_.count() > 0) history.arrived(core::SpinHistory::Clock::now(), false);
    // The host turns its own failures into Errors (CosimHost::guarded); anything else is
    // a bug of this thread's, which must not take the process down with it.
    std::vector<Outgoing> out;
    try {
      out = work ? (*work)(*host_) : host_->poll(SteadyClock::now());
    } catch (const std::exception& error) {
      spdlog::error("simulation {}: internal error: {}", host_->status().number, error.what());
    }
    if (work) ++calls_done_;
    const bool ended = host_->simulationsFinished() > 0;
    // A call that sends nothing while another is already queued is reported with that one
    // (calls_done counts both): each report wakes the network thread, and a client's
    // packages for one exchange arrive together.
    if (out.empty() && !ended && pending_.load(std::memory_order_acquire) > 0) continue;
    report_(std::move(out), host_->status(), ended, calls_done_);
    if (ended) {
      const std::lock_guard lock(mutex_);
      ended_ = true;
      queue_.clear();
      return;
    }
  }
}

}  // namespace demlink::server
