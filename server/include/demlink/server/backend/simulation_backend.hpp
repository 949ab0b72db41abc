#pragma once
/// The seam after the scene compiler: what runs a compiled scene. The compiler always
/// builds a core::World (validation, material mixing, the critical time-step check); a
/// backend then advances it. The native engine steps that world itself; another engine
/// (LIGGGHTS, liggghts_backend.hpp) takes the world as its input and copies its particles
/// back into it on syncParticles(), so every output reads one place.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "demlink/core/world.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// Which engine runs a scene (demlink-run / demlink-server --backend).
enum class BackendKind : std::uint8_t { Native, Liggghts };

/// "native" or "liggghts" (case-insensitive); throws core::InputError naming `field`.
[[nodiscard]] BackendKind parseBackendKind(const std::string& field, const std::string& value);

/// A SimulationBox of `scene` whose `backend` is set must name `backend` (the command
/// line's); throws core::InputError naming "components[i].simulation_box.backend" otherwise
/// (the scene's path; a co-simulation names the box instead, nameDeclaredField).
void requireBackendAgrees(const v1::Scene& scene, BackendKind backend);

class SimulationBackend {
 public:
  virtual ~SimulationBackend() = default;
  /// For logs: "native", "liggghts".
  [[nodiscard]] virtual std::string_view name() const = 0;
  /// Advances to the absolute step count `step` (>= stepCount()).
  virtual void advanceTo(std::uint64_t step) = 0;
  /// Steps taken since the world's step 0 [-].
  [[nodiscard]] virtual std::uint64_t stepCount() const = 0;
  /// Copies the engine's particles (position, velocity, angular velocity) into the
  /// compiled world; the native engine's world is its state already.
  virtual void syncParticles() = 0;
  /// The compiled world the outputs read (current after syncParticles()).
  [[nodiscard]] virtual const core::World& world() const = 0;
  /// Writes a checkpoint `demlink-run --backend <name()> --restore <base>` continues from,
  /// after a syncParticles(): natively the file `base` (core::writeCheckpointFile); LIGGGHTS
  /// adds its restart files next to it (LiggghtsBackend::writeCheckpoint, a collective).
  virtual void writeCheckpoint(const std::filesystem::path& base) = 0;
  /// Simulated time [s].
  [[nodiscard]] double time() const { return static_cast<double>(stepCount()) * world().settings().time_step; }
};

/// The shared-memory DEMLink engine: steps the compiled world.
class NativeBackend final : public SimulationBackend {
 public:
  /// `world` must outlive the backend; it is initialised here if it is not yet.
  explicit NativeBackend(core::World& world);
  [[nodiscard]] std::string_view name() const override { return "native"; }
  void advanceTo(std::uint64_t step) override;
  [[nodiscard]] std::uint64_t stepCount() const override { return world_.stepCount(); }
  void syncParticles() override {}
  [[nodiscard]] const core::World& world() const override { return world_; }
  void writeCheckpoint(const std::filesystem::path& base) override;

 private:
  core::World& world_;
};

}  // namespace demlink::server
