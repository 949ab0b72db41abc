#pragma once
/// The time step's driver: the stage calls a scene selected from the stage table
/// (stage_table.hpp), run in table order with one StepContext; the bookkeeping of
/// second half kicks owed across steps; and the sampled wall time of every stage.
/// It holds no particle data: the world gives it a function that runs one stage.
///
/// Owed half kicks: when every selected row is marked kick_may_be_owed, a step that
/// another step follows (within World::advance) and whose end the watchdog does not
/// inspect leaves its second half kick owed; the next step's first kick makes both
/// half kicks and the drift in one pass over the particles (kickTwiceAndDrift: the
/// same additions in the same order, so the same bits), or, in a frame at rest, the
/// step's pair loop makes them chunk by chunk (StepContext::next_kick_in_forces).
#include <array>
#include <chrono>
#include <cstdint>
#include <vector>

#include "demlink/core/step/stage_sampling.hpp"
#include "demlink/core/step/stage_table.hpp"
#include "demlink/core/parallel/thread_pool.hpp"

namespace demlink::core {

/// What a step's first kick still has to do (Stepper::takeFirstKick).
enum class FirstKick : std::uint8_t {
  kDoneInForces,   ///< the last step's pair loop made it (force and torque are zero)
  kTwiceAndDrift,  ///< the last step's second half kick is owed: both half kicks and the drift
  kHalfAndDrift,   ///< the usual half kick and drift
};

class Stepper {
 public:
  /// Selects the stage calls of a step for a scene with `features` (passes run
  /// inside `forces`, so they are no calls of their own) and whether kicks may be owed.
  void select(const SceneFeatures& features);
  /// The selected calls, in step order.
  [[nodiscard]] const std::vector<Stage>& calls() const { return calls_; }
  /// Whether a step may leave its second half kick owed in this scene.
  [[nodiscard]] bool kickDeferrable() const { return kick_deferrable_; }
  /// Second half kicks owed and paid by the next step's first kick so far.
  [[nodiscard]] std::uint64_t fusedKicks() const { return fused_kicks_; }

  /// The context of the step that starts at step count `step`; `endUnobserved`:
  /// another step follows within the same call and the watchdog does not inspect
  /// this step's end; `frameMoving`: the frame is not inertial.
  [[nodiscard]] StepContext beginStep(double dt, std::uint64_t step, ThreadPool* pool, bool endUnobserved,
                                      bool frameMoving) const;
  /// Runs the selected calls in order: runStage(stage, context) for each, timing a
  /// sample of steps when stage timing is on.
  template <class RunStage>
  void run(StepContext& context, RunStage&& runStage);

  /// Stage first kick: what it has to do, consuming what the last step left.
  [[nodiscard]] FirstKick takeFirstKick();
  /// Stage second half kick: true when it is to be made now; false when the pair
  /// loop made it or the context lets it be owed (then it is owed).
  [[nodiscard]] bool takeSecondKick(const StepContext& context);
  /// The force stage made (or did not make) the next step's first kick in its chunks.
  void setKickDoneInForces(bool done) { first_kick_done_ = done; }
  /// True (once) when a second half kick is owed: the caller makes it, so the state
  /// is whole when a call of steps ends.
  [[nodiscard]] bool takeOwedKick();

  /// Switches the sampled stage timing on or off (stage_sampling.hpp).
  void setTiming(bool on) { timing_ = on; }
  /// Estimated wall seconds of each stage since timing was switched on, by Stage.
  [[nodiscard]] const std::array<double, kStageCount>& stageSeconds() const { return stage_seconds_; }

 private:
  std::vector<Stage> calls_;
  bool kick_deferrable_ = false;
  bool half_kick_owed_ = false;   ///< the last step left its second half kick to the next one
  bool first_kick_done_ = false;  ///< the last step's pair loop ran this step's first kick
  std::uint64_t fused_kicks_ = 0;
  bool timing_ = false;
  std::array<double, kStageCount> stage_seconds_{};
};

template <class RunStage>
void Stepper::run(StepContext& context, RunStage&& runStage) {
  const std::uint64_t weight = timing_ ? stageTimingWeight(context.step) : 0;
  if (weight == 0) {
    for (const Stage stage : calls_) runStage(stage, context);
    return;
  }
  using Clock = std::chrono::steady_clock;
  Clock::time_point last = Clock::now();
  for (const Stage stage : calls_) {
    runStage(stage, context);
    const Clock::time_point now = Clock::now();
    stage_seconds_[static_cast<std::size_t>(stage)] +=
        static_cast<double>(weight) * std::chrono::duration<double>(now - last).count();
    last = now;
  }
}

}  // namespace demlink::core
