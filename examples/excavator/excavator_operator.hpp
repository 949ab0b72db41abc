#pragma once
/// The scripted operator: a state machine running N dig -> lift -> swing -> dump -> swing
/// back cycles by moving valve levers.
///
/// Why an operator that waits: a human operator does not push the bucket along a timed
/// path regardless of what happens; when the bucket meets resistance the machine slows
/// and the operator keeps the levers where they are until it catches up. Each phase
/// moves a task-space target (heading, pivot reach and height, bucket angle) from the
/// previous phase's end to its own end at a nominal pace, but the target only advances
/// while the machine follows it closely (largest joint error below kAdvanceError). The
/// levers are proportional to the joint errors (saturating at full opening), so a phase
/// in which the DEM loads the cylinders takes longer in simulated time: digging harder
/// slows the cycle, as the issue asks. A phase that cannot finish (a stalled cylinder)
/// ends after a timeout so the cycle always completes.
#include <array>
#include <string>
#include <vector>

#include "excavator_model.hpp"

namespace demlink::examples::excavator {

enum class Phase { kApproach, kPenetrate, kDrag, kCurl, kLift, kSwingToTruck, kDump, kSwingBack, kDone };

/// Short lower-case name of a phase (logs, CSV).
[[nodiscard]] const char* phaseName(Phase phase);

struct OperatorOptions {
  int cycles = 2;
  double dump_heading = 0.0;  ///< heading facing the truck [rad]
  double dig_heading = 1.5707963267948966;  ///< first dig heading [rad]
  double dump_reach = 5.2;    ///< bucket pivot distance from the swing axis at the dump [m]
};

class ExcavatorOperator {
 public:
  explicit ExcavatorOperator(OperatorOptions options);

  /// The machine's pose at t = 0 (bucket raised over the pit).
  [[nodiscard]] BucketTarget start() const;
  /// Valve commands for the next step of dt; advances the state machine.
  [[nodiscard]] std::array<double, 4> update(double dt, const ExcavatorModel& model);

  [[nodiscard]] Phase phase() const { return phase_; }
  [[nodiscard]] int cycle() const { return cycle_; }  ///< 0-based
  [[nodiscard]] bool done() const { return phase_ == Phase::kDone; }
  /// Phases that ended by timeout instead of reaching their target.
  [[nodiscard]] int timeouts() const { return timeouts_; }

 private:
  struct Segment {
    BucketTarget end;
    double duration = 1.0;  ///< nominal [s]
    double hold = 0.0;      ///< stay at the end for this long [s]
  };
  [[nodiscard]] Segment segment(Phase phase) const;
  [[nodiscard]] double digHeading(int cycle) const;
  /// Bucket above the far side of the dig strip, teeth down.
  [[nodiscard]] BucketTarget approachPose(int cycle) const;
  /// Extra depth of a cycle's dig [m].
  [[nodiscard]] static double deeper(int cycle);
  void enter(Phase phase, const BucketTarget& from);

  OperatorOptions options_;
  Phase phase_ = Phase::kApproach;
  int cycle_ = 0;
  int timeouts_ = 0;
  BucketTarget from_;
  Segment current_;
  double progress_ = 0.0;   ///< [0, 1]
  double elapsed_ = 0.0;    ///< in the phase [s]
  double held_ = 0.0;       ///< at the end [s]
};

}  // namespace demlink::examples::excavator
