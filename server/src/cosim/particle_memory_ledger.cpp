/// The particle memory of a server's simulations (contract in particle_memory_ledger.hpp).
#include "demlink/server/cosim/particle_memory_ledger.hpp"

#include <utility>

#include "demlink/core/world.hpp"
#include "demlink/server/scene/input_limits.hpp"

namespace demlink::server {

ParticleMemoryLedger::ParticleMemoryLedger(std::uint64_t budget) : budget_(budget) {}

ParticleMemoryLedger::Reservation::Reservation(std::shared_ptr<ParticleMemoryLedger> ledger, std::uint64_t bytes)
    : ledger_(std::move(ledger)), bytes_(bytes) {}

ParticleMemoryLedger::Reservation::Reservation(Reservation&& other) noexcept
    : ledger_(std::move(other.ledger_)), bytes_(std::exchange(other.bytes_, 0)) {}

ParticleMemoryLedger::Reservation::~Reservation() {
  if (ledger_) ledger_->release(bytes_);
}

std::optional<ParticleMemoryLedger::Reservation> ParticleMemoryLedger::reserve(
    const std::shared_ptr<ParticleMemoryLedger>& ledger, std::uint64_t bytes) {
  {
    const std::lock_guard lock(ledger->mutex_);
    if (bytes > ledger->budget_ - ledger->held_) return std::nullopt;
    ledger->held_ += bytes;
  }
  return std::optional<Reservation>(std::in_place, ledger, bytes);
}

std::uint64_t ParticleMemoryLedger::held() const {
  const std::lock_guard lock(mutex_);
  return held_;
}

void ParticleMemoryLedger::release(std::uint64_t bytes) {
  const std::lock_guard lock(mutex_);
  held_ -= bytes;
}

const std::shared_ptr<ParticleMemoryLedger>& processParticleMemory() {
  static const std::shared_ptr<ParticleMemoryLedger> ledger =
      std::make_shared<ParticleMemoryLedger>(particleMemoryBudget());
  return ledger;
}

std::uint64_t particleMemoryEstimate(const core::World& world) {
  std::uint64_t count = world.particles().size();
  for (const auto& body : world.deformableBodies()) count += body->nodeCount();
  return count * kBytesPerParticle;
}

}  // namespace demlink::server
