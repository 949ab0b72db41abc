/// The operator's script: where the bucket goes in each phase. The numbers place the
/// bucket (pivot reach r and height z from the swing axis at ground level, absolute bucket
/// angle phi) for examples/cosim/site_layout.hpp: the pit spans 2.5 .. 4.5 m ahead of the
/// axis when facing +y, its gravel surface is at z = 0; the truck bed's rim is at about
/// 1.8 m, 5.5 m from the axis towards +x. Dig pose: teeth down (phi = -90 deg), the open
/// side towards the machine; carry: teeth pointing back (phi = -185 deg), open side up;
/// dump: teeth forward and down (phi = -40 deg), open side down.
#include "excavator_operator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace demlink::examples::excavator {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
/// The target advances only while every joint is within this of it [rad].
constexpr double kAdvanceError = 0.15;
/// A phase ends when every joint is within this of its end target [rad].
constexpr double kArriveError = 0.015;
/// Lever gain: full opening at 1 / gain rad of error [1/rad].
constexpr std::array<double, 4> kGain{8.0, 8.0, 8.0, 8.0};
/// A phase gives up after timeout_factor x nominal duration + timeout_extra [s].
constexpr double kTimeoutFactor = 3.0;
constexpr double kTimeoutExtra = 3.0;

BucketTarget lerp(const BucketTarget& a, const BucketTarget& b, double s) {
  return {a.psi + s * (b.psi - a.psi), a.r + s * (b.r - a.r), a.z + s * (b.z - a.z), a.phi + s * (b.phi - a.phi)};
}

}  // namespace

const char* phaseName(Phase phase) {
  switch (phase) {
    case Phase::kApproach: return "approach";
    case Phase::kPenetrate: return "penetrate";
    case Phase::kDrag: return "drag";
    case Phase::kCurl: return "curl";
    case Phase::kLift: return "lift";
    case Phase::kSwingToTruck: return "swing_to_truck";
    case Phase::kDump: return "dump";
    case Phase::kSwingBack: return "swing_back";
    case Phase::kDone: return "done";
  }
  return "?";
}

ExcavatorOperator::ExcavatorOperator(OperatorOptions options) : options_(options) {
  from_ = start();
  enter(Phase::kApproach, from_);
}

BucketTarget ExcavatorOperator::start() const { return {options_.dig_heading, 4.0, 2.0, -100.0 * kDeg}; }

BucketTarget ExcavatorOperator::approachPose(int cycle) const {
  return {digHeading(cycle), 4.1, 1.2 - deeper(cycle), -85.0 * kDeg};
}

double ExcavatorOperator::deeper(int cycle) {
  // Strips dug a second time (after the five fresh ones) go 0.25 m deeper.
  return cycle >= 5 ? 0.25 : 0.0;
}

double ExcavatorOperator::digHeading(int cycle) const {
  // Each cycle digs a fresh strip: 0, +18, -18, +9, -9 deg from the first heading (about
  // 1.1 m apart at 3.5 m reach, the bucket is 1.2 m wide), then the same strips again.
  static constexpr std::array<double, 5> kOffsets{0.0, 18.0, -18.0, 9.0, -9.0};
  return options_.dig_heading + kOffsets[static_cast<std::size_t>(cycle) % kOffsets.size()] * kDeg;
}

ExcavatorOperator::Segment ExcavatorOperator::segment(Phase phase) const {
  const double dig = digHeading(cycle_);
  const double down = deeper(cycle_);
  switch (phase) {
    case Phase::kApproach: return {approachPose(cycle_), 1.5, 0.0};
    case Phase::kPenetrate: return {{dig, 3.9, 0.75 - down, -95.0 * kDeg}, 1.0, 0.0};
    case Phase::kDrag: return {{dig, 3.4, 0.62 - down, -120.0 * kDeg}, 1.5, 0.0};
    case Phase::kCurl: return {{dig, 3.3, 0.85 - down, -185.0 * kDeg}, 1.0, 0.2};
    // Lift clear of the pit, then raise further while swinging (operators overlap the two).
    case Phase::kLift: return {{dig, 3.6, 1.6, -185.0 * kDeg}, 1.0, 0.0};
    case Phase::kSwingToTruck:
      return {{options_.dump_heading, options_.dump_reach, 3.1, -185.0 * kDeg}, 2.2, 0.0};
    case Phase::kDump: return {{options_.dump_heading, options_.dump_reach, 3.1, -40.0 * kDeg}, 1.2, 0.5};
    case Phase::kSwingBack: {
      // Straight to the next cycle's approach pose (lowering while swinging), or home.
      if (cycle_ + 1 >= options_.cycles) return {start(), 2.2, 0.0};
      return {approachPose(cycle_ + 1), 2.2, 0.0};
    }
    case Phase::kDone: return {start(), 1.0, 0.0};
  }
  return {start(), 1.0, 0.0};
}

void ExcavatorOperator::enter(Phase phase, const BucketTarget& from) {
  phase_ = phase;
  from_ = from;
  current_ = segment(phase);
  progress_ = 0.0;
  elapsed_ = 0.0;
  held_ = 0.0;
}

std::array<double, 4> ExcavatorOperator::update(double dt, const ExcavatorModel& model) {
  if (phase_ == Phase::kDone) return {};
  elapsed_ += dt;
  const auto& q = model.angles();
  auto maxError = [&](const std::array<double, 4>& target) {
    double e = 0.0;
    for (std::size_t i = 0; i < 4; ++i) e = std::max(e, std::abs(target[i] - q[i]));
    return e;
  };
  const BucketTarget target = lerp(from_, current_.end, progress_);
  const std::array<double, 4> qTarget = model.inverseKinematics(target);
  if (maxError(qTarget) < kAdvanceError) progress_ = std::min(1.0, progress_ + dt / current_.duration);

  const bool arrived = progress_ >= 1.0 && maxError(model.inverseKinematics(current_.end)) < kArriveError;
  if (arrived) held_ += dt;
  const bool timedOut = elapsed_ > kTimeoutFactor * current_.duration + kTimeoutExtra + current_.hold;
  if ((arrived && held_ >= current_.hold) || timedOut) {
    if (timedOut && !arrived) ++timeouts_;
    const BucketTarget reached = current_.end;
    switch (phase_) {
      case Phase::kApproach: enter(Phase::kPenetrate, reached); break;
      case Phase::kPenetrate: enter(Phase::kDrag, reached); break;
      case Phase::kDrag: enter(Phase::kCurl, reached); break;
      case Phase::kCurl: enter(Phase::kLift, reached); break;
      case Phase::kLift: enter(Phase::kSwingToTruck, reached); break;
      case Phase::kSwingToTruck: enter(Phase::kDump, reached); break;
      case Phase::kDump: enter(Phase::kSwingBack, reached); break;
      case Phase::kSwingBack:
        ++cycle_;
        if (cycle_ >= options_.cycles) {
          phase_ = Phase::kDone;
          return {};
        }
        enter(Phase::kPenetrate, reached);
        break;
      case Phase::kDone: break;
    }
  }
  std::array<double, 4> commands{};
  const std::array<double, 4> qNow = model.inverseKinematics(lerp(from_, current_.end, progress_));
  for (std::size_t i = 0; i < 4; ++i) {
    // Opening the valve (extension) moves the joint in the sign of dl/dtheta.
    const double sign = model.leverArm(static_cast<int>(i), q[i]) < 0.0 ? -1.0 : 1.0;
    commands[i] = std::clamp(sign * kGain[i] * (qNow[i] - q[i]), -1.0, 1.0);
  }
  return commands;
}

}  // namespace demlink::examples::excavator
