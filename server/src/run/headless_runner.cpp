/// Headless run loop (contract in headless_runner.hpp).
///
/// Time is an integer step count: planRun converts the end time and the output
/// intervals once (core::intervalSteps: rounded, with a warning when off the step
/// grid); the RunDriver writes every output, so this file only steps and reports.
/// Progress is measured over the last report interval (steps/s and
/// particle-steps/s), and the estimated time left assumes that rate persists.
#include "demlink/server/run/headless_runner.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <algorithm>
#include <cmath>
#include <limits>

#include "demlink/core/checkpoint_file.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/core/components/sampled_component.hpp"
#include "demlink/server/run/contact_output_plan.hpp"
#include "demlink/server/run/deformable_series.hpp"
#include "demlink/server/run/frame_series.hpp"
#include "demlink/server/run/run_driver.hpp"

namespace demlink::server {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds)) return "?";
  if (seconds < 60.0) return fmt::format("{:.1f} s", seconds);
  const auto total = static_cast<long long>(std::llround(seconds));
  if (total < 3600) return fmt::format("{} min {:02} s", total / 60, total % 60);
  return fmt::format("{} h {:02} min", total / 3600, (total % 3600) / 60);
}

/// world.initialize(), with the engine's "simulation_box.<field>" errors renamed
/// to the SimulationBox's path in the scene.

void logCompileReport(const core::World& world, const TranslatedScene& scene, std::uint64_t endStep,
                      std::uint64_t frameEvery, const std::string& directory) {
  const core::TimeStepReport& report = world.timeStepReport();
  const core::SimulationSettings& settings = world.settings();
  std::string stages;
  for (const std::string& stage : world.activeStages()) stages += (stages.empty() ? "" : ", ") + stage;
  spdlog::info("compiled scene: particles {}, materials {}, planes {}", world.particles().size(),
               world.materials().size(), world.planes().size());
  spdlog::info("active stages: {}", stages);
  spdlog::info("pair kernel: {}", core::pairKernelName(world.pairKernel()));
  for (const std::string& line : report.describe()) spdlog::info("{}", line);
  const double percent = 100.0 * settings.time_step / report.limit;
  if (settings.time_step > report.limit) {
    spdlog::warn("time step: {:.4g} s = {:.1f} % of the limit (allowed by allow_unsafe_time_step)",
                 settings.time_step, percent);
  } else {
    spdlog::info("time step: {:.4g} s = {:.1f} % of the limit", settings.time_step, percent);
  }
  for (const std::string& line : choiceReportLines(scene, world)) {
    if (line.starts_with("warning: ")) {
      spdlog::warn("{}", line.substr(9));
    } else {
      spdlog::info("{}", line);
    }
  }
  for (const std::string& line : deformableReportLines(world)) spdlog::info("{}", line);
  spdlog::info("neighbour skin: {:.4g} m; gravity ({}, {}, {}) m/s^2", world.neighbourSkin(), settings.gravity.x(),
               settings.gravity.y(), settings.gravity.z());
  const std::uint64_t frames = (endStep + frameEvery - 1) / frameEvery + 1;
  spdlog::info("run: {} steps to t = {:.6g} s, a frame every {} steps ({} frames) -> {}", endStep,
               static_cast<double>(endStep) * settings.time_step, frameEvery, frames, directory);
}

/// Prints a progress line every `interval` wall seconds.
class ProgressMeter {
 public:
  ProgressMeter(double interval, std::uint64_t endStep, std::uint64_t firstStep)
      : interval_(interval), end_step_(endStep), last_step_(firstStep) {}

  void update(const core::World& world) {
    const Clock::time_point now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - last_time_).count();
    if (elapsed < interval_) return;
    const std::uint64_t step = world.stepCount();
    const double stepsPerSecond = static_cast<double>(step - last_step_) / elapsed;
    const double particleSteps = stepsPerSecond * static_cast<double>(world.particles().size());
    const double left = stepsPerSecond > 0.0 ? static_cast<double>(end_step_ - step) / stepsPerSecond
                                            : std::numeric_limits<double>::quiet_NaN();
    // Scenes with parallel bonds also show how many hold and how many broke.
    std::string bonds;
    if (world.bonds().hasRules()) {
      bonds = fmt::format(" | bonds {} intact, {} broken", world.bonds().counts().intact,
                          world.bonds().counts().broken);
    }
    spdlog::info("t = {:.4f} / {:.4f} s ({:.1f} %) | {:.0f} steps/s | {:.3g} M particle-steps/s | {} particles{} | "
                 "{} left",
                 world.time(), static_cast<double>(end_step_) * world.settings().time_step,
                 100.0 * static_cast<double>(step) / static_cast<double>(end_step_), stepsPerSecond,
                 particleSteps * 1.0e-6, world.particles().size(), bonds, formatDuration(left));
    last_time_ = now;
    last_step_ = step;
  }

 private:
  double interval_;
  std::uint64_t end_step_;
  Clock::time_point last_time_ = Clock::now();
  std::uint64_t last_step_;
};

}  // namespace

void checkHeadless(TranslatedScene& scene) {
  const RunOptions& run = scene.run;
  core::requirePositive(run.field_prefix + ".output.progress_interval_s", run.progress_interval);
  if (!scene.world.initialized()) scene.world.initialize();
  const RunPlan plan = planRun(run, scene.world.settings().time_step, true);
  for (const std::string& warning : plan.warnings) spdlog::warn("{}", warning);
  for (const std::string& warning : core::sampleScheduleWarnings(scene.world.components())) spdlog::warn("{}", warning);
}

RunSummary runHeadless(TranslatedScene& scene, const StepObserver& observer) {
  core::World& world = scene.world;
  const RunOptions& run = scene.run;
  const std::string& box = run.field_prefix;
  core::requirePositive(box + ".output.progress_interval_s", run.progress_interval);
  if (run.output_directory.empty()) {
    throw core::InputError(box + ".output.directory", "\"\"", "no output directory given");
  }

  const Clock::time_point initStart = Clock::now();
  if (!world.initialized()) {
    // Contact output first: initialize()'s force evaluation is the contacts' step-0 frame.
    const core::ContactOutputSettings contacts = contactOutputOf(run, planRun(run, world.settings().time_step, true));
    if (contacts.active()) world.setContactOutput(contacts);
    world.initialize();  // errors already name the scene (translateScene)
  }
  if (!run.restore_file.empty()) {
    core::restoreCheckpointFile(world, run.restore_file);
    spdlog::info("restored {} at t = {:.6g} s ({} particles)", run.restore_file, world.time(),
                 world.particles().size());
  }
  const double initialiseSeconds = secondsSince(initStart);
  const RunPlan plan = planRun(run, world.settings().time_step, true);
  for (const std::string& warning : plan.warnings) spdlog::warn("{}", warning);
  for (const std::string& warning : core::sampleScheduleWarnings(world.components())) spdlog::warn("{}", warning);
  for (const std::string& warning : world.warnings()) spdlog::warn("{}", warning);
  const std::uint64_t endStep = plan.end_step;
  if (world.stepCount() >= endStep) {
    throw core::InputError(box + ".end_time", core::formatValue(run.end_time),
                           "the restored checkpoint is already at t = " + core::formatValue(world.time()) +
                               " s; nothing left to run");
  }
  RunDriver driver(world, run, plan, run.output_directory, box + ".output.directory");
  driver.setInitialiseSeconds(initialiseSeconds);
  logCompileReport(world, scene, endStep, plan.frame_every > 0 ? plan.frame_every : endStep,
                   driver.directory().string());
  for (const std::filesystem::path& csv : driver.sensorFiles()) spdlog::info("sensor output: {}", csv.string());

  try {
    world.setStageTiming(true);  // the run log's per-stage rows
    driver.start(world);
    if (observer) observer(world);
    ProgressMeter progress(run.progress_interval, endStep, world.stepCount());
    while (world.stepCount() < endStep) {
      world.advance(1);  // the driver's outputs see every step
      driver.afterStep(world);
      if (observer) observer(world);
      progress.update(world);
    }
    driver.finish(world);
  } catch (const core::SimulationFault& fault) {
    spdlog::error("{}", fault.what());
    driver.fail(world, fault.what());
    throw;
  } catch (const std::exception& error) {
    driver.abort(error.what());
    throw;
  }
  const RunTiming& timing = driver.timing();
  const std::uint64_t particleSteps = timing.particle_steps;

  RunSummary summary;
  summary.steps = timing.steps;
  summary.checkpoints = timing.checkpoints;
  summary.frames = driver.frameCount();
  summary.final_particles = world.particles().size();
  summary.final_time = world.time();
  summary.final_kinetic_energy = world.kineticEnergy();
  summary.wall_seconds = std::max(timing.total_seconds, 1.0e-9);
  summary.output_directory = driver.directory();
  summary.bonds_created = world.bonds().counts().created();
  summary.bonds_broken = world.bonds().counts().broken;

  const FrameStats last = frameStats(world);
  spdlog::info("finished: {} steps to t = {:.6g} s in {} wall ({:.0f} steps/s, {:.3g} M particle-steps/s)",
               summary.steps, summary.final_time, formatDuration(summary.wall_seconds),
               static_cast<double>(summary.steps) / summary.wall_seconds,
               static_cast<double>(particleSteps) / summary.wall_seconds * 1.0e-6);
  spdlog::info("final state: {} particles ({} removed at the bounds), kinetic energy {:.4g} J, mean z {:.5g} m, "
               "max z {:.5g} m, {} neighbour builds",
               last.particles, world.removedAtBounds().count, last.kinetic_energy, last.mean_z, last.max_z,
               last.neighbour_builds);
  if (world.bonds().hasRules()) {
    const core::BondCounts& bonds = world.bonds().counts();
    spdlog::info("parallel bonds: {} created, {} broken, {} intact, {} lost with a removed particle",
                 bonds.created(), bonds.broken, bonds.intact, bonds.dropped);
  }
  spdlog::info("stage timing (sampled): {}", stageTimingSummary(world));
  for (const auto& component : world.components()) {
    if (const auto* source = dynamic_cast<const core::ParticleSource*>(component.get())) {
      if (source->report().shortfall_count > 0) {
        spdlog::warn("{}", source->summaryLine());
      } else {
        spdlog::info("{}", source->summaryLine());
      }
    }
  }
  for (const std::string& line : deformableFinalLines(world)) spdlog::info("{}", line);
  if (const auto bounds = world.currentBounds(); bounds && bounds->growing) {
    spdlog::info("bounds (growing): lower ({}, {}, {}) m, upper ({}, {}, {}) m", bounds->lower.x(), bounds->lower.y(),
                 bounds->lower.z(), bounds->upper.x(), bounds->upper.y(), bounds->upper.z());
  }
  std::string deformables;
  for (const auto& body : world.deformableBodies()) deformables += ", deformable_" + body->name() + ".pvd";
  spdlog::info("output: {} frames in {} (particles.pvd, summary.csv{}{}{})", summary.frames,
               summary.output_directory.string(), world.planes().empty() ? "" : ", planes.vtp",
               world.meshes().empty() ? "" : ", meshes.pvd", deformables);
  return summary;
}

}  // namespace demlink::server
