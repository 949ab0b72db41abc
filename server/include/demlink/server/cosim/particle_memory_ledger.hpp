#pragma once
/// The particle memory of every simulation a server runs, against one budget.
///
/// A scene alone may use up to particleMemoryBudget() (scene/input_limits.hpp, checked as
/// it is translated). Several simulations at once share that same budget: each compiled
/// simulation holds a reservation of its estimate (particles and deformable nodes at
/// kBytesPerParticle) until it ends, and a compile that would take the total past the
/// budget is refused with SERVER_BUSY naming what the others hold (docs/server.md,
/// "Limits and defaults"). Thread-safe: every simulation thread of a server shares one.
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>

namespace demlink::core {
class World;
}

namespace demlink::server {

class ParticleMemoryLedger {
 public:
  /// `budget`: the bytes all reservations together may hold.
  explicit ParticleMemoryLedger(std::uint64_t budget);

  /// Memory held for one simulation; given back when destroyed.
  class Reservation {
   public:
    Reservation(std::shared_ptr<ParticleMemoryLedger> ledger, std::uint64_t bytes);
    ~Reservation();
    Reservation(const Reservation&) = delete;
    Reservation& operator=(const Reservation&) = delete;
    Reservation(Reservation&& other) noexcept;
    Reservation& operator=(Reservation&&) = delete;
    [[nodiscard]] std::uint64_t bytes() const { return bytes_; }

   private:
    std::shared_ptr<ParticleMemoryLedger> ledger_;
    std::uint64_t bytes_ = 0;
  };

  /// `bytes` held for the caller, or nothing when the reservations held now leave less
  /// than that of the budget.
  [[nodiscard]] static std::optional<Reservation> reserve(const std::shared_ptr<ParticleMemoryLedger>& ledger,
                                                          std::uint64_t bytes);
  [[nodiscard]] std::uint64_t budget() const { return budget_; }
  /// Bytes the reservations hold now.
  [[nodiscard]] std::uint64_t held() const;

 private:
  void release(std::uint64_t bytes);

  const std::uint64_t budget_;
  mutable std::mutex mutex_;
  std::uint64_t held_ = 0;
};

/// The ledger of this process, over particleMemoryBudget(): what a host uses when its
/// options name none.
[[nodiscard]] const std::shared_ptr<ParticleMemoryLedger>& processParticleMemory();

/// A running world's estimate for the ledger: its particles and deformable nodes at
/// kBytesPerParticle each [bytes] (the rule the scene's own limit applies).
[[nodiscard]] std::uint64_t particleMemoryEstimate(const core::World& world);

}  // namespace demlink::server
