/// The simulation side of the live view (contract in live_view_hub.hpp).
#include "demlink/server/view/live_view_hub.hpp"

#include <algorithm>
#include <cmath>

#include "json_text.hpp"
#include "simulation_capture.hpp"

namespace demlink::server {
namespace {

std::int64_t nanoseconds(std::chrono::steady_clock::time_point time) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(time.time_since_epoch()).count();
}

std::atomic<std::uint64_t> next_hub_serial{1};

}  // namespace

thread_local LiveViewHub::ListingCache LiveViewHub::listing_cache_;

LiveViewHub::LiveViewHub() : serial_(next_hub_serial.fetch_add(1)) {}

LiveViewHub::~LiveViewHub() = default;

void LiveViewHub::claimDefaultIfNone(const core::World& world, Listed& slot) {
  // A plain load first: offer() runs after every step of every simulation, and a CAS would
  // take the shared cache line each time.
  const core::World* current = default_.load(std::memory_order_acquire);
  if (current != nullptr || !default_.compare_exchange_strong(current, &world)) return;
  // The default is captured whether or not a page is open (at once: its scene is described
  // then), so the first page to connect gets it without waiting.
  std::lock_guard lock(listing_mutex_);
  applyDemand(slot);
  ++listing_version_;
}

LiveViewHub::Listed* LiveViewHub::findSlot(const core::World* world) {
  for (const auto& slot : slots_) {
    if (slot->world.load(std::memory_order_relaxed) == world) return slot.get();
  }
  return nullptr;
}

LiveViewHub::Listed* LiveViewHub::shownSlot(SimulationId simulation) {
  if (simulation == kDefaultSimulation) {
    const core::World* world = default_.load(std::memory_order_acquire);
    return world == nullptr ? nullptr : findSlot(world);
  }
  for (const auto& slot : slots_) {
    if (slot->id == simulation && slot->world.load(std::memory_order_relaxed) != nullptr) return slot.get();
  }
  return nullptr;
}

LiveViewHub::Listed& LiveViewHub::noteListing(const core::World& world) {
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
  return *slot;
}

void LiveViewHub::announce(const core::World& world, const std::string& name) {
  Listed& slot = noteListing(world);
  std::lock_guard lock(listing_mutex_);
  slot.name = name;
  ++listing_version_;
}

void LiveViewHub::release(const core::World& world) {
  {
    std::lock_guard lock(listing_mutex_);
    if (Listed* slot = findSlot(&world)) {
      slot->world.store(nullptr, std::memory_order_relaxed);
      slot->capture.reset();
      slot->period_ns.store(0, std::memory_order_relaxed);
      slot->next_due_ns.store(kNever, std::memory_order_relaxed);
    }
    // Under the listing's lock, so that a world claiming the default sees its slot's state.
    const core::World* current = &world;
    default_.compare_exchange_strong(current, nullptr);
    ++listing_version_;
  }
  if (notify_) notify_();  // the pages' lists lose it; its pages move to the default
}

std::optional<std::string> LiveViewHub::cannotFollow(SimulationId id) {
  std::lock_guard lock(listing_mutex_);
  if (id != kDefaultSimulation && shownSlot(id) != nullptr) return std::nullopt;
  std::vector<std::uint64_t> ids;
  for (const auto& slot : slots_) {
    if (slot->world.load(std::memory_order_relaxed) != nullptr) ids.push_back(slot->id);
  }
  std::sort(ids.begin(), ids.end());
  std::string open;
  for (const std::uint64_t open_id : ids) open += (open.empty() ? "" : ", ") + std::to_string(open_id);
  return "no open simulation has this id (open: " + (open.empty() ? std::string("none") : open) + ")";
}

void LiveViewHub::applyDemand(Listed& slot) {
  const bool isDefault = slot.world.load(std::memory_order_relaxed) == default_.load(std::memory_order_acquire);
  bool followed = false;
  double rate = 0.0;
  CaptureFields fields;
  for (const SimulationDemand& demand : demands_) {
    if (demand.simulation != slot.id && !(isDefault && demand.simulation == kDefaultSimulation)) continue;
    followed = true;
    rate = std::max(rate, demand.frames_per_second);
    fields.speed = fields.speed || demand.fields.speed;
    fields.force = fields.force || demand.fields.force;
  }
  if (!followed && !isDefault) {
    slot.capture.reset();
    slot.period_ns.store(0, std::memory_order_relaxed);
    slot.next_due_ns.store(kNever, std::memory_order_relaxed);
    return;
  }
  slot.want_speed.store(fields.speed, std::memory_order_relaxed);
  slot.want_force.store(fields.force, std::memory_order_relaxed);
  const std::int64_t period = rate > 0.0 ? static_cast<std::int64_t>(std::llround(1.0e9 / rate)) : 0;
  const std::int64_t before = slot.period_ns.exchange(period, std::memory_order_relaxed);
  if (!slot.capture) {
    // New captures start at once: their scene is described then.
    slot.capture = std::make_shared<SimulationCapture>();
    slot.next_due_ns.store(0, std::memory_order_relaxed);
  } else if (period > 0 && (before == 0 || period < before)) {
    // A page that just arrived (or asked for a higher rate) gets its next frame now, not
    // one old period later.
    const std::int64_t now = nanoseconds(Clock::now());
    if (slot.next_due_ns.load(std::memory_order_relaxed) > now) slot.next_due_ns.store(now, std::memory_order_relaxed);
  } else if (period == 0 && before != 0) {
    slot.next_due_ns.store(kNever, std::memory_order_relaxed);
  }
}

void LiveViewHub::setDemand(const std::vector<SimulationDemand>& demands) {
  std::lock_guard lock(listing_mutex_);
  demands_ = demands;
  for (const auto& slot : slots_) {
    if (slot->world.load(std::memory_order_relaxed) != nullptr) applyDemand(*slot);
  }
}

void LiveViewHub::offer(const core::World& world) {
  Listed& slot = noteListing(world);
  claimDefaultIfNone(world, slot);
  const std::int64_t due = slot.next_due_ns.load(std::memory_order_relaxed);
  if (due == kNever) return;  // nobody follows it, or none of its pages wants a frame
  const Clock::time_point now = Clock::now();
  if (nanoseconds(now) < due) return;
  capture(world, slot, now);
}

void LiveViewHub::offerNow(const core::World& world) {
  Listed& slot = noteListing(world);
  claimDefaultIfNone(world, slot);
  capture(world, slot, Clock::now());
}

void LiveViewHub::capture(const core::World& world, Listed& slot, Clock::time_point now) {
  std::shared_ptr<SimulationCapture> into;
  {
    std::lock_guard lock(listing_mutex_);
    into = slot.capture;
    if (!into) {
      slot.next_due_ns.store(kNever, std::memory_order_relaxed);
      return;
    }
  }
  const CaptureFields fields{slot.want_speed.load(std::memory_order_relaxed),
                             slot.want_force.load(std::memory_order_relaxed)};
  into->capture(world, fields, now, versions_);
  captures_.fetch_add(1, std::memory_order_relaxed);
  {
    std::lock_guard lock(listing_mutex_);
    if (slot.capture == into) {  // else its pages left meanwhile
      const std::int64_t period = slot.period_ns.load(std::memory_order_relaxed);
      slot.next_due_ns.store(period > 0 ? nanoseconds(now) + period : kNever, std::memory_order_relaxed);
    }
  }
  if (notify_) notify_();
}

std::shared_ptr<SimulationCapture> LiveViewHub::shownCapture(SimulationId simulation) {
  std::lock_guard lock(listing_mutex_);
  const Listed* slot = shownSlot(simulation);
  return slot == nullptr ? nullptr : slot->capture;
}

std::string LiveViewHub::sceneJson(SimulationId simulation) {
  const std::shared_ptr<SimulationCapture> shown = shownCapture(simulation);
  return shown ? shown->sceneJson() : std::string();
}

std::uint64_t LiveViewHub::sceneVersion(SimulationId simulation) {
  const std::shared_ptr<SimulationCapture> shown = shownCapture(simulation);
  return shown ? shown->sceneVersion() : 0;
}

const ViewSnapshot* LiveViewHub::snapshot(SimulationId simulation, std::uint32_t /*index*/, std::uint64_t& version) {
  reading_ = shownCapture(simulation);
  version = 0;
  return reading_ ? reading_->snapshot(version) : nullptr;
}

std::string LiveViewHub::simulationsJson(SimulationId simulation) {
  std::lock_guard lock(listing_mutex_);
  std::vector<const Listed*> open;
  for (const auto& slot : slots_) {
    if (slot->world.load(std::memory_order_relaxed) != nullptr) open.push_back(slot.get());
  }
  std::sort(open.begin(), open.end(), [](const Listed* a, const Listed* b) { return a->id < b->id; });
  const Listed* shown = shownSlot(simulation);
  std::string list;
  for (const Listed* slot : open) {
    if (!list.empty()) list += ',';
    const std::string name = slot->name.empty() ? "simulation " + std::to_string(slot->id) : slot->name;
    list += fmt::format(R"({{"id":{},"name":{},"particles":{},"time":{}}})", slot->id, jsonString(name),
                        slot->particles.load(std::memory_order_relaxed),
                        jsonNumber(slot->time.load(std::memory_order_relaxed)));
  }
  return fmt::format(R"({{"kind":"simulations","followed":{},"simulations":[{}]}})", shown ? shown->id : 0, list);
}

std::size_t LiveViewHub::captureSets() {
  std::lock_guard lock(listing_mutex_);
  return static_cast<std::size_t>(
      std::count_if(slots_.begin(), slots_.end(), [](const auto& slot) { return slot->capture != nullptr; }));
}

std::uint64_t LiveViewHub::simulationsVersion() {
  std::lock_guard lock(listing_mutex_);
  return listing_version_;
}

}  // namespace demlink::server
