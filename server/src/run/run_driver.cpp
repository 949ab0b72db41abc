/// A run's outputs (contract in run_driver.hpp).
///
/// Every write is timed into RunTiming::output_seconds, so the run log can split the wall
/// time into stepping and output.
#include "demlink/server/run/run_driver.hpp"

#include <spdlog/spdlog.h>

#include <spdlog/fmt/fmt.h>

#include "demlink/core/components/sampled_component.hpp"
#include "demlink/core/checkpoint_file.hpp"
#include "demlink/core/step/interval_steps.hpp"
#include "demlink/server/run/contact_output_plan.hpp"
#include "demlink/server/run/output_directory.hpp"
#include "demlink/server/scene/particle_csv.hpp"

namespace demlink::server {
namespace {

/// A state holding a NaN or an infinity is never written: the run stops on it as the
/// watchdog would, and the files already written keep the last finite state.
void requireFiniteState(const core::World& world, const std::string& output) {
  const std::string what = world.nonFiniteState();
  if (!what.empty()) {
    throw core::SimulationFault("non_finite", what + " is not finite; " + output + " not written",
                                world.stepCount());
  }
}

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::filesystem::path claimed(const std::filesystem::path& directory, bool overwrite, const std::string& field) {
  claimOutputDirectory(directory, overwrite, field);
  return directory;
}

/// Runs `write` and adds its wall time to `seconds`.
template <class Write>
void timed(double& seconds, Write&& write) {
  const Clock::time_point begin = Clock::now();
  write();
  seconds += secondsSince(begin);
}

/// Contact output is on and the world recorded the contacts of its current step.
bool contactsRecordedNow(const core::World& world, const RunPlan& plan) {
  return plan.contact_every > 0 && world.contactSnapshot().valid && world.contactSnapshot().step == world.stepCount();
}

}  // namespace

RunPlan planRun(const RunOptions& run, double timeStep, bool endTimeRequired) {
  RunPlan plan;
  const std::string& box = run.field_prefix;
  auto convert = [&](const std::string& field, double seconds, core::ZeroInterval zero) {
    core::IntervalRule rule;
    rule.zero = zero;
    core::IntervalSteps steps = core::intervalSteps(box + field, seconds, timeStep, rule);
    if (!steps.warning.empty()) plan.warnings.push_back(std::move(steps.warning));
    return steps.steps;
  };
  plan.end_step =
      convert(".end_time", run.end_time, endTimeRequired ? core::ZeroInterval::Refused : core::ZeroInterval::Off);
  plan.frame_every = convert(".output.vtk_interval", run.vtk_interval, core::ZeroInterval::Off);
  plan.checkpoint_every = convert(".output.checkpoint_interval", run.checkpoint_interval, core::ZeroInterval::Off);
  plan.contact_every = convert(".output.contact_interval", run.contact_interval, core::ZeroInterval::Off);
  return plan;
}

bool RunPlan::frameDue(std::uint64_t step) const {
  return (frame_every > 0 && step % frame_every == 0) || step == end_step;
}

bool RunPlan::checkpointDue(std::uint64_t step) const {
  return checkpoint_every > 0 && step % checkpoint_every == 0;
}

std::string RunPlan::checkpointName(std::uint64_t step) const {
  return core::checkpointFileName(step / checkpoint_every);
}

RunDriver::RunDriver(core::World& world, const RunOptions& run, RunPlan plan, const std::filesystem::path& directory,
                     const std::string& directoryField)
    : run_(run),
      plan_(std::move(plan)),
      frames_(claimed(directory, run.overwrite, directoryField), directoryField),
      deformables_(directory, world),
      log_(directory / "run_log.csv") {
  run_.output_directory = directory.string();
  const core::ContactOutputSettings contacts = contactOutputOf(run_, plan_);
  if (contacts.active()) world.setContactOutput(contacts);
  log_.writeConfiguration(world, run_, plan_.end_step);
  sensor_files_ = core::writeSamplesToCsv(world.components(), directory);
}

double RunDriver::wallSeconds() const { return secondsSince(start_); }

void RunDriver::start(const core::World& world) {
  start_ = Clock::now();
  first_step_ = world.stepCount();
  last_step_ = first_step_;
  first_build_ = world.neighbourList().buildCount();
  timed(timing_.output_seconds, [&] {
    frames_.writePlanes(world);
    frames_.writeFrame(world, 0.0);
    deformables_.writeFrame(world);
  });
  last_frame_step_ = world.stepCount();
  // The step-0 frame (or a restored step's, if recorded): the runner asked for contact
  // output before initialize() (contact_output_plan.hpp).
  if (contactsRecordedNow(world, plan_)) writeContacts(world);
}



void RunDriver::writeFrame(const core::World& world) {
  requireFiniteState(world, "VTK frame " + std::to_string(frames_.frameCount()));
  timed(timing_.output_seconds, [&] {
    frames_.writeFrame(world, secondsSince(start_));
    deformables_.writeFrame(world);
  });
  last_frame_step_ = world.stepCount();
}

void RunDriver::writeCheckpoint(const core::World& world, const std::string& name) {
  requireFiniteState(world, name);
  timed(timing_.output_seconds, [&] {
    if (checkpoint_writer_) {
      checkpoint_writer_(directory() / name);
    } else {
      core::writeCheckpointFile(world, directory() / name);
    }
  });
  ++timing_.checkpoints;
}

void RunDriver::writeContacts(const core::World& world) {
  const core::ContactSnapshot& snapshot = world.contactSnapshot();
  const std::string stem = fmt::format("contacts_{:06}", contact_entries_.size());
  requireFiniteState(world, stem + ".vtp/.csv");
  timed(timing_.output_seconds, [&] {
    core::writeContactsVtp((directory() / (stem + ".vtp")).string(), snapshot.contacts);
    core::writeContactsCsv((directory() / (stem + ".csv")).string(), snapshot.contacts);
    contact_entries_.push_back({world.time(), stem + ".vtp"});
    core::writePvd((directory() / "contacts.pvd").string(), contact_entries_);
  });
}

void RunDriver::afterStep(const core::World& world) {
  const std::uint64_t step = world.stepCount();
  timing_.particle_steps += world.particles().size() * (step - last_step_);
  last_step_ = step;
  deformables_.afterStep(world);
  if (plan_.frameDue(step)) writeFrame(world);
  if (plan_.contact_every > 0 && step % plan_.contact_every == 0 && contactsRecordedNow(world, plan_)) {
    writeContacts(world);
  }
  if (plan_.checkpointDue(step)) writeCheckpoint(world, plan_.checkpointName(step));
}

void RunDriver::finish(const core::World& world, const std::string& reason) {
  if (ended_) return;
  if (const std::string what = world.nonFiniteState(); !what.empty()) {
    fail(world, what + " is not finite at the end (" + reason + ")");
    return;
  }
  try {
    if (last_frame_step_ != world.stepCount()) writeFrame(world);
    if (run_.final_checkpoint) writeCheckpoint(world, core::kFinalCheckpointFileName);
    if (run_.final_particles_csv) {
      timed(timing_.output_seconds, [&] { writeParticleCsv(world, directory() / "particles_final.csv"); });
    }
  } catch (const std::exception& error) {
    abort(error.what());
    throw;
  }
  ended_ = true;
  timing_.total_seconds = secondsSince(start_);
  timing_.steps = world.stepCount() - first_step_;
  timing_.neighbour_builds = world.neighbourList().buildCount() - first_build_;
  timing_.frames = frames_.frameCount();
  if (!reason.empty()) log_.add("timing", "finish_reason", reason);
  log_.writeTiming(world, timing_);
}

void RunDriver::fail(const core::World& world, const std::string& why) {
  if (ended_) return;
  try {
    writeCheckpoint(world, core::kFinalCheckpointFileName);
  } catch (const std::exception& error) {
    // A non-finite state is not written: the last checkpoint and frame on disk are the
    // last finite state.
    spdlog::error("final checkpoint not written: {}", error.what());
  }
  ended_ = true;
  timing_.total_seconds = secondsSince(start_);
  timing_.steps = world.stepCount() - first_step_;
  log_.add("timing", "status", "failed: " + why);
}

void RunDriver::abort(const std::string& why) {
  if (ended_) return;
  ended_ = true;
  log_.add("timing", "status", "aborted: " + why);
}

}  // namespace demlink::server
