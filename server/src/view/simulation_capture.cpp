/// One simulation's captures (contract in simulation_capture.hpp).
#include "simulation_capture.hpp"

namespace demlink::server {

SimulationCapture::SimulationCapture()
    : back_(std::make_unique<ViewSnapshot>()),
      ready_(std::make_unique<ViewSnapshot>()),
      front_(std::make_unique<ViewSnapshot>()) {}

void SimulationCapture::capture(const core::World& world, const CaptureFields& fields, Clock::time_point now,
                                std::atomic<std::uint64_t>& versions) {
  const bool newScene = &world != last_world_ || (captured_before_ && world.stepCount() < last_step_);
  std::string scene;
  if (newScene) {
    last_world_ = &world;
    captured_before_ = false;
    scene = describeScene(world);
  }
  captureSnapshot(world, fields, *back_);
  ViewStatus& status = back_->status;
  if (captured_before_) {
    const double wall = std::chrono::duration<double>(now - last_wall_).count();
    status.real_time_factor = wall > 0.0 ? (status.time - last_time_) / wall : 0.0;
    status.steps_per_second = wall > 0.0 ? static_cast<double>(status.step - last_step_) / wall : 0.0;
  } else {
    initial_mass_ = status.particle_mass - status.inserted_mass + status.removed_mass;
  }
  status.initial_mass = initial_mass_;
  captured_before_ = true;
  last_wall_ = now;
  last_time_ = status.time;
  last_step_ = status.step;
  std::lock_guard lock(mutex_);
  if (newScene) {
    scene_ = std::move(scene);
    scene_version_ = versions.fetch_add(1, std::memory_order_relaxed) + 1;
  }
  std::swap(back_, ready_);
  ready_version_ = versions.fetch_add(1, std::memory_order_relaxed) + 1;
}

std::string SimulationCapture::sceneJson() {
  std::lock_guard lock(mutex_);
  return scene_;
}

std::uint64_t SimulationCapture::sceneVersion() {
  std::lock_guard lock(mutex_);
  return scene_version_;
}

const ViewSnapshot* SimulationCapture::snapshot(std::uint64_t& version) {
  std::lock_guard lock(mutex_);
  if (ready_version_ != front_version_) {
    std::swap(ready_, front_);
    front_version_ = ready_version_;
  }
  version = front_version_;
  return front_version_ > 0 ? front_.get() : nullptr;
}

}  // namespace demlink::server
