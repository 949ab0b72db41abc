#pragma once
/// Spin-then-block for the exchange waits (the server's network loop, the client's
/// receive): spinFor (spin_wait.hpp), spun only when what the same waiter's recent waits
/// saw says the event will come within the budget and from a partner that is awake.
///
/// Why: a spin pays only when its event comes before the budget runs out, and when the
/// partner answers at once. Two situations break that:
/// - the partner is asleep. A waiter that was away (working, or paced: a client in real
///   time sleeps ~1 ms between exchanges) for longer than the budget since its last event
///   finds its partner blocked: the partner started waiting when it sent that event and
///   has spun out its budget since. The answer then comes only after the partner's
///   wake-up, and spinning for it holds a core the woken partner could have used (on a
///   2-vCPU VM the paced round trip got slower: 45 against 31 us). Block at once.
/// - the event comes late. A server loop waiting for a client that exchanges every
///   millisecond sees its event ~1 ms after it starts waiting; each spin burns its whole
///   budget in vain (5 % of a core at 50 us per ms). After kMissesBeforeBackOff waits in a
///   row that were late (a spin that ran out, or a blocked wait far beyond the budget:
///   kLateFactor) the waiter blocks at once, and tries a spin again once every
///   kRetryEvery waits, so it spins again soon after its events come within the budget
///   (back-to-back exchanges). A blocked wait that ended within the budget (wake-up
///   included) ends the back-off at once.
/// Header-only, like spin_wait.hpp, for the client.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>

#include "demlink/core/parallel/spin_wait.hpp"

namespace demlink::core {

/// Exchange waits, all threads of the process, that blocked at once on their history.
struct SpinHistoryStats {
  std::uint64_t partner_asleep = 0;  ///< away longer than the budget since the last event
  std::uint64_t late = 0;            ///< backed off after late events
};

/// One waiter's recent waits (not thread-safe: one per waiting thread or loop).
class SpinHistory {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::uint32_t kMissesBeforeBackOff = 3;
  static constexpr std::uint32_t kRetryEvery = 32;
  /// A blocked wait longer than kLateFactor budgets was late even allowing for the
  /// wake-up (tens of microseconds) it includes [-].
  static constexpr std::int64_t kLateFactor = 4;

  /// What the next wait should do.
  enum class Advice { kSpin, kBlockPartnerAsleep, kBlockLate };

  /// The rule, without state: a wait that starts `away` after the waiter's last event
  /// (nullopt: no event yet), after `misses` late waits in a row and `skipped` waits not
  /// spun since the last try.
  [[nodiscard]] static Advice adviceFor(std::optional<std::chrono::nanoseconds> away, std::uint32_t misses,
                                        std::uint32_t skipped, std::chrono::nanoseconds budget) {
    if (away && *away > budget) return Advice::kBlockPartnerAsleep;
    if (misses < kMissesBeforeBackOff || skipped + 1 >= kRetryEvery) return Advice::kSpin;
    return Advice::kBlockLate;
  }

  /// Advice for a wait that starts at `now` with `budget`; remembers the start (see arrived).
  [[nodiscard]] Advice begin(Clock::time_point now, std::chrono::nanoseconds budget) {
    beginBlocking(now, budget);
    std::optional<std::chrono::nanoseconds> away;
    if (last_event_) away = now - *last_event_;
    const Advice advice = adviceFor(away, misses_, skipped_, budget);
    if (advice == Advice::kBlockLate) {
      ++skipped_;
      counters().late.fetch_add(1, std::memory_order_relaxed);
    } else if (advice == Advice::kSpin) {
      skipped_ = 0;
    } else {
      counters().partner_asleep.fetch_add(1, std::memory_order_relaxed);
    }
    return advice;
  }

  /// A wait that starts at `now` and blocks without advice (spinning is off: `budget` 0).
  void beginBlocking(Clock::time_point now, std::chrono::nanoseconds budget) {
    start_ = now;
    budget_ = budget;
    spun_out_ = false;
  }

  /// The wait begun last saw its event at `now`: `spun` true when a spin saw it, false
  /// after a block.
  void arrived(Clock::time_point now, bool spun) {
    last_event_ = now;
    const std::chrono::nanoseconds waited = now - start_;
    if (spun) {
      misses_ = 0;
    } else if (spun_out_ || (budget_.count() > 0 && waited > kLateFactor * budget_)) {
      ++misses_;
    } else if (waited <= budget_) {
      misses_ = 0;
    }
  }
  /// The wait's spin ran out of budget: it was late (the waiter blocks, then arrived()).
  void spunOut() { spun_out_ = true; }

  /// Late waits in a row [-].
  [[nodiscard]] std::uint32_t misses() const { return misses_; }

  /// Process-wide counts of the waits that blocked at once on their history.
  [[nodiscard]] static SpinHistoryStats stats() {
    return {counters().partner_asleep.load(std::memory_order_relaxed), counters().late.load(std::memory_order_relaxed)};
  }

 private:
  struct Counters {
    std::atomic<std::uint64_t> partner_asleep{0};
    std::atomic<std::uint64_t> late{0};
  };
  static Counters& counters() {
    static Counters c;
    return c;
  }

  std::optional<Clock::time_point> last_event_;
  Clock::time_point start_{};
  std::chrono::nanoseconds budget_{0};
  std::uint32_t misses_ = 0;   ///< late waits in a row
  std::uint32_t skipped_ = 0;  ///< waits not spun since the last try
  bool spun_out_ = false;      ///< the current wait's spin ran out of budget
};

/// The spin half of an exchange wait guided by `history`: spinFor(party, budget, ready)
/// when the history advises a spin. True: ready() returned true (the event is recorded).
/// False: the caller blocks in its own way and then calls history.arrived(now, false).
template <class Ready>
bool spinFor(SpinHistory& history, SpinGate::Party party, std::chrono::nanoseconds budget, Ready&& ready) {
  if (budget.count() <= 0) {
    history.beginBlocking(SpinHistory::Clock::now(), budget);
    return false;
  }
  if (history.begin(SpinHistory::Clock::now(), budget) != SpinHistory::Advice::kSpin) return false;
  bool polled = false;
  const bool done = spinFor(party, budget, [&] {
    polled = true;
    return ready();
  });
  if (done) {
    history.arrived(SpinHistory::Clock::now(), true);
  } else if (polled) {
    history.spunOut();
  }
  return done;
}

}  // namespace demlink::core
