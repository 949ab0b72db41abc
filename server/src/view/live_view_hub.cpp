/// The simulation side of the live view (contract in live_view_hub.hpp).
#include "demlink/server/view/live_view_hub.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "json_text.hpp"

namespace demlink::server {
namespace {

constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();

std::int64_t nanoseconds(std::chrono::steady_clock::time_point time) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(time.time_since_epoch()).count();
}

std::atomic<std::uint64_t> next_hub_serial{1};

}  // namespace

thread_local LiveViewHub::ListingCache LiveViewHub::listing_cache_;

LiveViewHub::LiveViewHub()
    : serial_(next_hub_serial.fetch_add(1)),
      next_due_ns_(kNever),
      period_ns_(0),
      back_(std::make_unique<ViewSnapshot>()),
      ready_(std::make_unique<ViewSnapshot>()),
      front_(std::make_unique<ViewSnapshot>()) {}

bool LiveViewHub::follows(const core::World& world) {
  // A plain load first: offer() runs after every step of every simulation, and a CAS would
  // take the shared cache line each time.
  const core::World* followed = followed_.load(std::memory_order_acquire);
  if (followed != nullptr) return followed == &world;
  if (!followed_.compare_exchange_strong(followed, &world)) return followed == &world;
  // A newly followed world captures at once: its scene is described whether or not a page
  // is open, so the first page to connect gets it without waiting.
  next_due_ns_.store(0, std::memory_order_relaxed);
  {
    std::lock_guard lock(listing_mutex_);
    ++listing_version_;
  }
  return true;
}

LiveViewHub::Listed* LiveViewHub::findSlot(const core::World* world) {
  for (const auto& slot : slots_) {
    if (slot->world.load(std::memory_order_relaxed) == world) return slot.get();
  }
  return nullptr;
}

void LiveViewHub::noteListing(const core::World& world) {
  ListingCache& cache = listing_cache_;
  Listed* slot = cache.slot;
  if (cache.hub != serial_ || cache.world != &world || slot->world.load(std::memory_order_relaxed) != &world) {
    bool added = false;
    {
      std::lock_guard lock(listing_mutex_);
      slot = findSlot(&world);
      if (slot == nullptr) {
        slot = findSlot(nullptr);
        if (slot == nullptr) slot = slots_.emplace_back(std::make_unique<Listed>()).get();
        slot->id = next_id_++;
        slot->name.clear();
        slot->world.store(&world, std::memory_order_relaxed);
        ++listing_version_;
        added = true;
      }
    }
    cache = {serial_, &world, slot};
    if (added && notify_) notify_();  // the pages' lists gain it
  }
  slot->particles.store(world.particles().size(), std::memory_order_relaxed);
  slot->time.store(world.time(), std::memory_order_relaxed);
}

void LiveViewHub::announce(const core::World& world, const std::string& name) {
  noteListing(world);
  std::lock_guard lock(listing_mutex_);
  if (Listed* slot = findSlot(&world)) {
    slot->name = name;
    ++listing_version_;
  }
}

void LiveViewHub::release(const core::World& world) {
  {
    std::lock_guard lock(listing_mutex_);
    if (Listed* slot = findSlot(&world)) slot->world.store(nullptr, std::memory_order_relaxed);
    ++listing_version_;
    // Under the listing's lock, so that follow() never hands the view to a closed world.
    const core::World* followed = &world;
    followed_.compare_exchange_strong(followed, nullptr);
  }
  if (notify_) notify_();  // the pages' lists lose it
}

std::optional<std::string> LiveViewHub::follow(std::uint64_t id) {
  std::lock_guard lock(listing_mutex_);
  const core::World* target = nullptr;
  std::string open;
  for (const auto& slot : slots_) {
    const core::World* world = slot->world.load(std::memory_order_relaxed);
    if (world == nullptr) continue;
    if (slot->id == id) target = world;
    open += (open.empty() ? "" : ", ") + std::to_string(slot->id);
  }
  if (target == nullptr) {
    return "no open simulation has this id (open: " + (open.empty() ? std::string("none") : open) + ")";
  }
  if (followed_.load(std::memory_order_acquire) == target) return std::nullopt;
  {
    // The world followed so far finishes any capture first, and captures no more.
    std::lock_guard capture(capture_mutex_);
    followed_.store(target, std::memory_order_release);
    next_due_ns_.store(0, std::memory_order_relaxed);
  }
  ++listing_version_;
  return std::nullopt;
}

void LiveViewHub::offer(const core::World& world) {
  noteListing(world);
  if (!follows(world)) return;
  const Clock::time_point now = Clock::now();
  if (nanoseconds(now) < next_due_ns_.load(std::memory_order_relaxed)) return;
  std::lock_guard lock(capture_mutex_);
  if (followed_.load(std::memory_order_relaxed) != &world) return;  // a page chose another meanwhile
  capture(world, now);
}

void LiveViewHub::offerNow(const core::World& world) {
  noteListing(world);
  if (!follows(world)) return;
  std::lock_guard lock(capture_mutex_);
  if (followed_.load(std::memory_order_relaxed) != &world) return;
  capture(world, Clock::now());
}

void LiveViewHub::capture(const core::World& world, Clock::time_point now) {
  // Another world than the last one (or a clock that went back) is a new simulation.
  const bool newScene = &world != last_world_ || (captured_before_ && world.stepCount() < last_step_);
  std::string scene;
  if (newScene) {
    last_world_ = &world;
    captured_before_ = false;
    scene = describeScene(world);
  }
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
    // A new scene and its first frame are published together, so a page that is sent the
    // scene is never sent a frame of the simulation before it.
    std::lock_guard lock(mutex_);
    if (newScene) {
      scene_ = std::move(scene);
      ++scene_version_;
    }
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

std::string LiveViewHub::simulationsJson() {
  std::lock_guard lock(listing_mutex_);
  std::vector<const Listed*> open;
  for (const auto& slot : slots_) {
    if (slot->world.load(std::memory_order_relaxed) != nullptr) open.push_back(slot.get());
  }
  std::sort(open.begin(), open.end(), [](const Listed* a, const Listed* b) { return a->id < b->id; });
  const core::World* followed = followed_.load(std::memory_order_acquire);
  std::uint64_t followedId = 0;
  std::string list;
  for (const Listed* slot : open) {
    if (slot->world.load(std::memory_order_relaxed) == followed) followedId = slot->id;
    if (!list.empty()) list += ',';
    const std::string name = slot->name.empty() ? "simulation " + std::to_string(slot->id) : slot->name;
    list += fmt::format(R"({{"id":{},"name":{},"particles":{},"time":{}}})", slot->id, jsonString(name),
                        slot->particles.load(std::memory_order_relaxed),
                        jsonNumber(slot->time.load(std::memory_order_relaxed)));
  }
  return fmt::format(R"({{"kind":"simulations","followed":{},"simulations":[{}]}})", followedId, list);
}

std::uint64_t LiveViewHub::simulationsVersion() {
  std::lock_guard lock(listing_mutex_);
  return listing_version_;
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
