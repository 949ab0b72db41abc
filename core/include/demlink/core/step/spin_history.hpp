#pragma once
/// Spin-then-block for a waiter whose event often comes late: spinFor (spin_wait.hpp)
/// guided by what the same waiter's recent spins gave.
///
/// Why: a server loop waiting for a client that exchanges every millisecond (a client in
/// real time) sees its event ~1 ms after it starts waiting; each spin then burns its
/// whole budget in vain, 5 % of a core at 50 us per ms. After kMissesBeforeBackOff spins
/// in a row that ran out of budget the waiter blocks at once, and tries a spin again once
/// every kRetryEvery waits, so it spins again soon after its events start coming within
/// the budget (back-to-back exchanges). Header-only, like spin_wait.hpp, for the client.
#include <chrono>
#include <cstdint>

#include "demlink/core/step/spin_wait.hpp"

namespace demlink::core {

/// One waiter's recent spins (not thread-safe: one per waiting thread or loop).
class SpinHistory {
 public:
  static constexpr std::uint32_t kMissesBeforeBackOff = 3;
  static constexpr std::uint32_t kRetryEvery = 32;

  /// Whether the next wait should try to spin (counts the waits it skips).
  [[nodiscard]] bool shouldSpin() {
    if (misses_ < kMissesBeforeBackOff) return true;
    if (++skipped_ < kRetryEvery) {
      ++backed_off_;
      return false;
    }
    skipped_ = 0;
    return true;
  }
  /// Records a spin that ran: its event came while spinning (ready) or the budget ran out.
  void record(bool ready) { misses_ = ready ? 0 : misses_ + 1; }
  /// Waits that blocked at once because of the recent misses [-].
  [[nodiscard]] std::uint64_t backedOff() const { return backed_off_; }

 private:
  std::uint32_t misses_ = 0;   ///< spins in a row that ran out of budget
  std::uint32_t skipped_ = 0;  ///< waits not spun since the last try
  std::uint64_t backed_off_ = 0;
};

/// spinFor(party, budget, ready) when `history` advises a spin; a spin the gate refused
/// (ready() never polled) is not recorded. Same result as spinFor.
template <class Ready>
bool spinFor(SpinHistory& history, SpinGate::Party party, std::chrono::nanoseconds budget, Ready&& ready) {
  if (budget.count() <= 0 || !history.shouldSpin()) return false;
  bool polled = false;
  const bool done = spinFor(party, budget, [&] {
    polled = true;
    return ready();
  });
  if (polled) history.record(done);
  return done;
}

}  // namespace demlink::core
