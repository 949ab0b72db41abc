/// The simulation side of the live view (contract in live_view_hub.hpp).
#include "demlink/server/view/live_view_hub.hpp"

#include <cmath>
#include <limits>

namespace demlink::server {
namespace {

constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();

std::int64_t nanoseconds(std::chrono::steady_clock::time_point time) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(time.time_since_epoch()).count();
}

}  // namespace

LiveViewHub::LiveViewHub()
    : next_due_ns_(kNever),
      period_ns_(0),
      back_(std::make_unique<ViewSnapshot>()),
      ready_(std::make_unique<ViewSnapshot>()),
      front_(std::make_unique<ViewSnapshot>()) {}

bool LiveViewHub::follows(const core::World& world) {
  // A plain load first: offer() runs after every step of every simulation, and a CAS would
  // take the shared cache line each time. The claiming CAS (seq_cst) sees everything the
  // releasing thread wrote to the buffers.
  const core::World* followed = followed_.load(std::memory_order_acquire);
  if (followed != nullptr) return followed == &world;
  return followed_.compare_exchange_strong(followed, &world) || followed == &world;
}

void LiveViewHub::release(const core::World& world) {
  const core::World* followed = &world;
  followed_.compare_exchange_strong(followed, nullptr);
}

void LiveViewHub::offer(const core::World& world) {
  if (!follows(world)) return;
  // The scene is described once per simulation whether or not a page is open, so the
  // first page to connect gets it without waiting for a step.
  if (&world != last_world_ || (captured_before_ && world.stepCount() < last_step_)) {
    last_world_ = &world;
    captured_before_ = false;
    std::string scene = describeScene(world);
    std::lock_guard lock(mutex_);
    scene_ = std::move(scene);
    ++scene_version_;
  }
  const Clock::time_point now = Clock::now();
  if (captured_before_ && nanoseconds(now) < next_due_ns_.load(std::memory_order_relaxed)) return;
  capture(world, now);
}

void LiveViewHub::offerNow(const core::World& world) {
  if (!follows(world)) return;
  if (!captured_before_ || &world != last_world_) {
    offer(world);
    return;
  }
  capture(world, Clock::now());
}

void LiveViewHub::capture(const core::World& world, Clock::time_point now) {
  const CaptureFields fields{want_speed_.load(std::memory_order_relaxed), want_force_.load(std::memory_order_relaxed)};
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
  {
    std::lock_guard lock(mutex_);
    std::swap(back_, ready_);
    ++ready_version_;
  }
  captures_.fetch_add(1, std::memory_order_relaxed);
  const std::int64_t period = period_ns_.load(std::memory_order_relaxed);
  next_due_ns_.store(period > 0 ? nanoseconds(now) + period : kNever, std::memory_order_relaxed);
  if (notify_) notify_();
}

std::string LiveViewHub::sceneJson() {
  std::lock_guard lock(mutex_);
  return scene_;
}

std::uint64_t LiveViewHub::sceneVersion() {
  std::lock_guard lock(mutex_);
  return scene_version_;
}

const ViewSnapshot* LiveViewHub::snapshot(std::uint32_t /*index*/, std::uint64_t& version) {
  std::lock_guard lock(mutex_);
  if (ready_version_ > front_version_) {
    std::swap(ready_, front_);
    front_version_ = ready_version_;
  }
  version = front_version_;
  return front_version_ > 0 ? front_.get() : nullptr;
}

void LiveViewHub::setDemand(double framesPerSecond, CaptureFields fields) {
  want_speed_.store(fields.speed, std::memory_order_relaxed);
  want_force_.store(fields.force, std::memory_order_relaxed);
  const std::int64_t period =
      framesPerSecond > 0.0 ? static_cast<std::int64_t>(std::llround(1.0e9 / framesPerSecond)) : 0;
  const std::int64_t before = period_ns_.exchange(period, std::memory_order_relaxed);
  // A page that just arrived (or asked for a higher rate) gets its next frame now, not
  // one old period later.
  if (period > 0 && (before == 0 || period < before)) {
    next_due_ns_.store(nanoseconds(Clock::now()), std::memory_order_relaxed);
  } else if (period == 0) {
    next_due_ns_.store(kNever, std::memory_order_relaxed);
  }
}

}  // namespace demlink::server
