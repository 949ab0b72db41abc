/// One running co-simulation (contract in cosim_simulation.hpp).
///
/// The outputs are the headless runner's (RunDriver: frames, checkpoints, run log, final
/// files, on the steps planned by the compiler) with two additions to the step: after
/// every world step each rigid body's coupling adds the step's wrench to its impulses,
/// and at a stop the couplings whose interval ends there snap their mesh onto the target
/// before the outputs are read; before every world step each client-driven deformable body
/// gets its driving pose and twist at the start of that step (the sample advanced by its
/// twist; the body carries the pose through the step itself). At a stop the driver writes
/// after the snap (and LIGGGHTS's hand-over), so a checkpoint there holds the world the
/// next interval starts from: the state a restored simulation continues
/// (demlink-server --restore). On LIGGGHTS the backend writes the checkpoints (with its
/// restart files) at the stops, where the compiled world holds its particles, instead of
/// the driver after every step.
#include "demlink/server/cosim/cosim_simulation.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <fstream>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/checkpoint_file.hpp"
#include "demlink/server/cosim/cosim_inputs.hpp"
#include "demlink/server/run/run_log.hpp"

namespace demlink::server {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

CosimSimulation::CosimSimulation(CompiledSimulation compiled, const std::filesystem::path& outputDirectory,
                                 const CosimOptions& options)
    : compiled_(std::move(compiled)),
      directory_(outputDirectory),
      outputs_(compiled_.components.size()),
      before_engine_(options.before_engine),
      stop_stepping_(options.stop_stepping),
      turns_(options.turns),
      stop_consensus_(options.stop_consensus),
      step_observer_(options.step_observer),
      close_observer_(options.close_observer) {
  core::World& w = world();
  for (std::size_t i = 0; i < compiled_.components.size(); ++i) {
    const CosimComponent& c = compiled_.components[i];
    if (c.interval_steps > 0) scheduler_.add(i, c.interval_steps);
    if (c.kind_case == v1::ComponentDeclaration::kRigidBody && c.mesh && c.interval_steps > 0) {
      couplings_.emplace(i, core::CoupledMotion(*c.mesh, c.motion));
    }
  }
  if (!options.restore_file.empty()) restoreFrom(options.restore_file);
  backend_checkpoints_ = options.backend != BackendKind::Native;
  if (!options.mirror) {
    RunOptions run = compiled_.scene->run;
    run.restore_file = options.restore_file.string();
    RunPlan plan = compiled_.plan;
    if (backend_checkpoints_) {
      run.final_checkpoint = false;
      plan.checkpoint_every = 0;
    }
    driver_ = std::make_unique<RunDriver>(w, run, plan, directory_,
                                          compiled_.box_name + ".simulation_box.output.directory");
    std::ofstream report(directory_ / "compile_report.txt");
    report << compiled_.report.text();
  }
  if (options.backend == BackendKind::Liggghts) {
    beforeEngine();
    backend_ = options.liggghts(w, options.mirror ? std::filesystem::path() : directory_ / "liggghts.log",
                                options.restore_file);
  } else {
    backend_ = std::make_unique<NativeBackend>(w);
  }
  w.setStageTiming(true);  // the run log's per-stage rows
  if (driver_) driver_->start(w);
  if (options.open_observer) options.open_observer(w, directory_.filename().string());
  if (step_observer_) step_observer_(w);
}

CosimSimulation::~CosimSimulation() {
  if (close_observer_) close_observer_(world());
  // Closing LIGGGHTS is a collective of every rank.
  if (backend_ && backend_->name() != "native") beforeEngine();
}

void CosimSimulation::restoreFrom(const std::filesystem::path& checkpoint) {
  core::World& w = world();
  if (!w.initialized()) w.initialize();
  core::restoreCheckpointFile(w, checkpoint);
  const std::uint64_t step = w.stepCount();
  if (compiled_.end_step > 0 && step >= compiled_.end_step) {
    throw core::InputError("restore", checkpoint.string(),
                           fmt::format("the checkpoint is at step {}, at or after the end step {}: nothing left to run",
                                       step, compiled_.end_step));
  }
  // Only a stop where every exchanged component is due carries no interval in progress (a
  // coupling's target, its impulses), which the checkpoint does not hold.
  for (const CosimComponent& c : compiled_.components) {
    if (c.interval_steps > 0 && step % c.interval_steps != 0) {
      throw core::InputError("restore", checkpoint.string(),
                             fmt::format("the checkpoint is at step {}, where component \"{}\" (exchanged every {} "
                                         "steps) is in the middle of an interval; restore one written at a step where "
                                         "every exchanged component is due",
                                         step, c.name, c.interval_steps));
    }
  }
  scheduler_.startAt(step);
  spdlog::info("restored {} at step {} (t = {:.6g} s, {} particles)", checkpoint.string(), step, w.time(),
               w.particles().size());
}

void CosimSimulation::beforeEngine() const {
  if (before_engine_) before_engine_();
}

const core::CoupledMotion* CosimSimulation::coupling(std::size_t index) const {
  const auto it = couplings_.find(index);
  return it == couplings_.end() ? nullptr : &it->second;
}

std::vector<v1::DataPackage> CosimSimulation::initialOutputs(ConnectionId owner) {
  std::vector<v1::DataPackage> out;
  for (std::size_t i = 0; i < compiled_.components.size(); ++i) {
    const CosimComponent& c = compiled_.components[i];
    if (c.owner != owner || c.interval_steps == 0) continue;
    core::IntervalWrench wrench;
    if (c.mesh) {
      wrench.force = world().meshes()[*c.mesh].force();
      wrench.torque = world().meshes()[*c.mesh].torque();
    }
    out.push_back(outputs_.outputOf(i, c, world(), wrench));
  }
  return out;
}

std::optional<v1::Error> CosimSimulation::accept(ConnectionId from, const v1::DataPackage& package) {
  const std::uint32_t id = package.component_id();
  if (id == 0 || id > compiled_.components.size()) {
    return makeError(v1::Error::UNKNOWN_COMPONENT,
                     "no component with id " + std::to_string(id) + " (ids 1.." +
                         std::to_string(compiled_.components.size()) + ")",
                     "", "data.component_id", true);
  }
  const std::size_t index = id - 1;
  const CosimComponent& c = compiled_.components[index];
  if (c.owner != from) {
    return makeError(v1::Error::UNKNOWN_COMPONENT,
                     "component " + std::to_string(id) + " (\"" + c.name + "\") is not declared by this connection",
                     c.name, "data.component_id", true);
  }
  const std::optional<std::uint64_t> expected = scheduler_.expectedStep(index);
  if (!expected) {
    return makeError(v1::Error::UNKNOWN_COMPONENT,
                     "component \"" + c.name + "\" is not exchanged (communication_interval 0, or its client said Bye)",
                     c.name, "data.component_id", true);
  }
  const std::uint64_t now = scheduler_.currentStep();
  if (package.step() != *expected || *expected != now) {
    std::string why = "expected step " + std::to_string(*expected) + ", received step " + std::to_string(package.step());
    if (package.step() == *expected) {
      why = "step " + std::to_string(package.step()) + " is not due yet (the world is at step " + std::to_string(now) +
            "; wait for the answer to the previous package)";
    }
    return makeError(v1::Error::OUT_OF_ORDER, "component \"" + c.name + "\": " + why, c.name, "data.step", true);
  }
  if (auto bad = checkInput(c, package, compiled_.time_step)) return bad;
  if (auto bad = refusedByEngine(c, package)) return bad;
  if (scheduler_.offer(index, package.step()) != ExchangeScheduler::Offer::Accepted) {
    return makeError(v1::Error::OUT_OF_ORDER, "component \"" + c.name + "\": package not accepted", c.name,
                     "data.step", true);
  }
  inputs_[index] = package;
  return std::nullopt;
}

std::optional<v1::Error> CosimSimulation::refusedByEngine(const CosimComponent& c, const v1::DataPackage& package) {
  if (backend_->name() == "native" || !package.has_simulation_box_input()) return std::nullopt;
  // LIGGGHTS is given the bounds, the frame and gravity once, at the start (liggghts_script.hpp).
  const v1::SimulationBoxInput& input = package.simulation_box_input();
  if (input.has_frame() && !frameOf(input.frame()).isInertial()) {
    return makeError(v1::Error::INVALID_INPUT,
                     "component \"" + c.name + "\": the LIGGGHTS backend has no moving frame; run it on the native "
                     "backend",
                     c.name, "data.simulation_box_input.frame", true);
  }
  if (input.has_gravity() &&
      core::Vec3(input.gravity().x(), input.gravity().y(), input.gravity().z()) != world().gravity()) {
    return makeError(v1::Error::INVALID_INPUT,
                     "component \"" + c.name + "\": the LIGGGHTS backend cannot change gravity during a run",
                     c.name, "data.simulation_box_input.gravity", true);
  }
  return std::nullopt;
}

void CosimSimulation::retire(ConnectionId owner) {
  for (std::size_t i = 0; i < compiled_.components.size(); ++i) {
    if (compiled_.components[i].owner != owner) continue;
    scheduler_.retire(i);
    inputs_.erase(i);
    if (auto it = couplings_.find(i); it != couplings_.end()) it->second.hold(world().mesh(it->second.meshIndex()));
    if (auto it = drives_.find(i); it != drives_.end()) {
      // The nodes stop where they are.
      DeformableDrive& drive = it->second;
      drive.sample = core::advancePose(drive.sample, drive.twist,
                                       static_cast<double>(world().stepCount() - drive.step) * compiled_.time_step);
      drive.twist = {};
      drive.step = world().stepCount();
    }
  }
}

void CosimSimulation::stepWorld() {
  core::World& w = world();
  for (const auto& [index, drive] : drives_) {
    const double seconds = static_cast<double>(w.stepCount() - drive.step) * compiled_.time_step;
    const core::RigidPose pose = core::advancePose(drive.sample, drive.twist, seconds);
    w.deformableBody(*compiled_.components[index].deformable)
        .setDrivenPose(pose.position, pose.orientation, drive.twist.linear, drive.twist.angular);
  }
  backend_->advanceTo(w.stepCount() + 1);  // couplings and outputs see every step
  for (auto& [index, coupling] : couplings_) coupling.afterStep(w.meshes()[coupling.meshIndex()], w.settings().time_step);
  if (step_observer_) step_observer_(w);
}

CosimSimulation::Advance CosimSimulation::advance() {
  core::World& w = world();
  Advance out;
  for (const auto& [index, package] : inputs_) {
    const CosimComponent& c = compiled_.components[index];
    if (package.has_rigid_body_input()) {
      core::CoupledMotion& coupling = couplings_.at(index);
      coupling.beginInterval(w.mesh(coupling.meshIndex()), w.settings().time_step, poseOf(package.rigid_body_input()),
                             twistOf(package.rigid_body_input()), c.interval_steps);
    } else if (package.has_deformable_body_input()) {
      drives_[index] = {poseOf(package.deformable_body_input()), twistOf(package.deformable_body_input()),
                        w.stepCount()};
    } else if (package.has_simulation_box_input()) {
      const v1::SimulationBoxInput& input = package.simulation_box_input();
      if (input.has_gravity()) {
        w.setGravity({input.gravity().x(), input.gravity().y(), input.gravity().z()});
      }
      if (input.has_frame()) w.setFrameMotion(frameOf(input.frame()));
    } else {
      applyComponentInput(c, package, w);
    }
  }
  inputs_.clear();
  const std::optional<std::uint64_t> stop = scheduler_.nextStop(compiled_.end_step);
  if (!stop) return out;
  const Clock::time_point begin = Clock::now();
  const std::uint64_t first = w.stepCount();
  beforeEngine();
  std::optional<SteppingTurns::Turn> turn;
  if (turns_) turn.emplace(*turns_, stop_stepping_.get());
  while (w.stepCount() < *stop) {
    // Between two steps, the one place an interval of any length can end early.
    bool halt = turn ? !turn->mayStep() : stop_stepping_ && stop_stepping_->load(std::memory_order_relaxed);
    if (stop_consensus_) halt = stop_consensus_(halt);
    if (halt) {
      backend_->syncParticles();
      outputs_.addStepping(w.stepCount() - first, secondsSince(begin));
      out.stepped = w.stepCount() > first;
      out.interrupted = true;
      return out;
    }
    stepWorld();
    if (driver_ && w.stepCount() < *stop) driver_->afterStep(w);
  }
  turn.reset();
  // The outputs at the stop read the particles from the compiled world (no-op natively).
  backend_->syncParticles();
  outputs_.addStepping(w.stepCount() - first, secondsSince(begin));
  out.stepped = true;
  for (const std::size_t index : scheduler_.advanceTo(*stop)) {
    const CosimComponent& c = compiled_.components[index];
    core::IntervalWrench wrench;
    if (auto it = couplings_.find(index); it != couplings_.end()) wrench = it->second.endInterval(w.mesh(it->second.meshIndex()), w.settings().time_step);
    out.answers.emplace_back(*c.owner, outputs_.outputOf(index, c, w, wrench));
  }
  // The stop's frame and checkpoint, with the meshes on their targets.
  if (driver_) driver_->afterStep(w);
  // The first stop at or after each checkpoint step (every rank: a collective on LIGGGHTS).
  if (const std::uint64_t every = compiled_.plan.checkpoint_every;
      backend_checkpoints_ && every > 0 && w.stepCount() / every > first / every) {
    backend_->writeCheckpoint(directory_ / core::checkpointFileName(w.stepCount() / every));
  }
  out.end_reached = compiled_.end_step > 0 && *stop >= compiled_.end_step;
  return out;
}

void CosimSimulation::finish(const std::string& reason) {
  if (backend_checkpoints_ && !finished_ && compiled_.scene->run.final_checkpoint) {
    finished_ = true;
    beforeEngine();
    backend_->writeCheckpoint(directory_ / core::kFinalCheckpointFileName);
  }
  finished_ = true;
  if (!driver_) return;
  driver_->finish(world(), reason);
  // The measured part of the compile report: known only once the run has stepped.
  std::ofstream report(directory_ / "compile_report.txt", std::ios::app);
  report << "stage timing (sampled, " << world().stepCount() << " steps): " << stageTimingSummary(world()) << "\n";
}

}  // namespace demlink::server
