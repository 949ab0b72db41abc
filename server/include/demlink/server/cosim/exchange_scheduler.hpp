#pragma once
/// The sample grid of a co-simulation (docs/cosim.md, "Scheduler"): which components are
/// due at which step, whose package is still missing, and how far the world may advance.
///
/// Why a class without a world: the rule is pure integer arithmetic on steps and is the
/// part most worth testing exhaustively. Component c with interval n_c is due at the steps
/// k n_c (k = 0, 1, ...). At a step where components are due, the world waits for a package
/// from each of them; then it advances to the next step at which any component is due (or
/// the end step) and the components whose interval ends there are answered. A component
/// whose client left (retire()) is no longer due. Time is an integer step count throughout.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace demlink::server {

class ExchangeScheduler {
 public:
  /// Why offer() refused a package.
  enum class Offer : std::uint8_t {
    Accepted,
    NotExchanged,     ///< the component has no interval (or was retired)
    AlreadyReceived,  ///< its package for the current step is already in
    NotDue,           ///< the step is its next due step, but the world is not there yet
    WrongStep,        ///< the step is not its next due step
  };

  /// Adds component `index` (any number, unique) exchanged every `intervalSteps` (>= 1) steps.
  void add(std::size_t index, std::uint64_t intervalSteps);
  /// The component takes no further part (its client said Bye).
  void retire(std::size_t index);

  /// Starts the grid at `step` instead of 0 (a simulation restored from a checkpoint at
  /// that step), before any package: every component must be due there. Throws
  /// std::invalid_argument otherwise.
  void startAt(std::uint64_t step);
  /// The world's current step [-].
  [[nodiscard]] std::uint64_t currentStep() const { return step_; }
  /// The step of the component's next package: the current step while it is due and
  /// missing, otherwise its next multiple of the interval. nullopt: not exchanged.
  [[nodiscard]] std::optional<std::uint64_t> expectedStep(std::size_t index) const;
  /// Records a package of `index` for `step`.
  Offer offer(std::size_t index, std::uint64_t step);
  /// Active components due now whose package is missing.
  [[nodiscard]] std::vector<std::size_t> missing() const;
  /// True when every component due now has reported (also when none is due).
  [[nodiscard]] bool complete() const { return missing().empty(); }
  /// Any component still exchanged.
  [[nodiscard]] bool anyActive() const;
  /// The next step after the current one at which an active component is due, capped at
  /// endStep when endStep > 0; nullopt when nothing is active and endStep is 0 (or reached).
  [[nodiscard]] std::optional<std::uint64_t> nextStop(std::uint64_t endStep) const;
  /// Moves to `step` (> current) and returns the active components whose interval ends
  /// there (step a multiple of their interval), in the order they were added.
  std::vector<std::size_t> advanceTo(std::uint64_t step);
  /// The component's interval [steps]; 0 if unknown.
  [[nodiscard]] std::uint64_t interval(std::size_t index) const;

 private:
  struct Entry {
    std::size_t index = 0;
    std::uint64_t interval = 0;
    bool active = true;
    bool received = false;  ///< package for the current step is in
  };
  [[nodiscard]] const Entry* find(std::size_t index) const;
  [[nodiscard]] bool dueAt(const Entry& e, std::uint64_t step) const { return e.active && step % e.interval == 0; }

  std::vector<Entry> entries_;
  std::uint64_t step_ = 0;
};

}  // namespace demlink::server
