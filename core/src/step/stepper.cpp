/// The step's driver (contract in stepper.hpp).
#include "demlink/core/step/stepper.hpp"

namespace demlink::core {

void Stepper::select(const SceneFeatures& features) {
  const std::vector<Stage> selected = selectStages(features);
  calls_.clear();
  for (const Stage stage : selected) {
    if (!stageInfo(stage).pass) calls_.push_back(stage);
  }
  kick_deferrable_ = kickMayBeOwed(selected);
}

StepContext Stepper::beginStep(double dt, std::uint64_t step, ThreadPool* pool, bool endUnobserved,
                               bool frameMoving) const {
  StepContext context{dt, step, pool};
  context.may_owe_kick = kick_deferrable_ && endUnobserved;
  // A step that owes its second half kick may as well pay it, with the next step's first
  // kick and drift, inside its pair loop: each chunk then kicks the rows it has just
  // finished while they are in its thread's cache, instead of a pass of its own over every
  // column at the next step's start. The same additions in the same order, so the same
  // bits (Determinism tests).
  context.next_kick_in_forces = context.may_owe_kick && !frameMoving;
  context.force_step = step + 1;  // the forces of a step belong to its end
  context.force_weight = dt;
  return context;
}

FirstKick Stepper::takeFirstKick() {
  if (first_kick_done_) {
    first_kick_done_ = false;
    ++fused_kicks_;
    return FirstKick::kDoneInForces;
  }
  if (half_kick_owed_) {
    half_kick_owed_ = false;
    ++fused_kicks_;
    return FirstKick::kTwiceAndDrift;
  }
  return FirstKick::kHalfAndDrift;
}

bool Stepper::takeSecondKick(const StepContext& context) {
  if (first_kick_done_) return false;  // paid in the pair loop, with the next step's first kick
  if (context.may_owe_kick) {
    half_kick_owed_ = true;
    return false;
  }
  return true;
}

bool Stepper::takeOwedKick() {
  if (!half_kick_owed_) return false;
  half_kick_owed_ = false;
  return true;
}

}  // namespace demlink::core
