#pragma once
/// What a scene component sees of the world it runs in: the clock and the settings, the
/// particles, walls, clumps, deformable bodies and bonds to read, and the few changes a
/// component makes (insert particles and clumps, remove particles, drive a deformable
/// body; at set-up, declare the particles a source will insert and join the world).
/// World implements it.
///
/// Why an interface and not World: a component depends on the engine's data, never on
/// the facade that steps it, so components/ sits below world.hpp and a component cannot
/// reach the step's machinery (stages, kicks, threads, checkpoints). The calls are
/// virtual; a component makes a handful of them per step, never one per particle.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "demlink/core/bonds/bond_set.hpp"
#include "demlink/core/deformable/deformable_body.hpp"
#include "demlink/core/materials/material.hpp"
#include "demlink/core/particles/clump_body.hpp"
#include "demlink/core/particles/clump_template.hpp"
#include "demlink/core/particles/particle_arrays.hpp"
#include "demlink/core/simulation_settings.hpp"
#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/walls/plane_wall.hpp"
#include "demlink/core/world_state.hpp"

namespace demlink::core {

class WorldComponent;

class ComponentWorld {
 public:
  virtual ~ComponentWorld() = default;

  // The clock and what the user chose.
  /// Time now [s]: the start of the step in insert_remove, its end in observe.
  [[nodiscard]] virtual double time() const = 0;
  [[nodiscard]] virtual std::uint64_t stepCount() const = 0;
  [[nodiscard]] virtual const SimulationSettings& settings() const = 0;

  // What a component reads.
  [[nodiscard]] virtual const ParticleArrays& particles() const = 0;
  [[nodiscard]] virtual const std::vector<Material>& materials() const = 0;
  [[nodiscard]] virtual const std::vector<PlaneWall>& planes() const = 0;
  [[nodiscard]] virtual const std::vector<MeshBody>& meshes() const = 0;
  [[nodiscard]] virtual const std::vector<ClumpTemplate>& clumpTemplates() const = 0;
  [[nodiscard]] virtual const std::vector<ClumpBody>& clumps() const = 0;
  [[nodiscard]] virtual const std::vector<std::unique_ptr<DeformableBody>>& deformableBodies() const = 0;
  [[nodiscard]] virtual const BondSet& bonds() const = 0;

  // What a component changes.
  /// Adds a validated sphere; returns its id. fieldPrefix names it in errors.
  virtual std::uint64_t addParticle(const ParticleSpec& spec, const std::string& fieldPrefix) = 0;
  /// Adds a rigid clump of a registered template; returns its clump id.
  virtual std::uint64_t addClump(const ClumpSpec& spec, const std::string& fieldPrefix) = 0;
  /// Removes every particle for which `remove(slot)` is true (a clump as a whole) and adds
  /// them to `tally`.
  virtual void removeParticles(const std::function<bool(std::size_t)>& remove, RemovalTally& tally) = 0;
  /// The deformable body at `index` (std::out_of_range otherwise), to drive its pose.
  [[nodiscard]] virtual DeformableBody& deformableBody(std::size_t index) = 0;

  // Set-up, before the world is initialised.
  /// Particles of `material` down to `minRadius` [m] will be inserted later: the time-step
  /// check and the default skin take them into account.
  virtual void declareFutureParticles(std::uint32_t material, double minRadius, const std::string& fieldPrefix) = 0;
  /// The world takes the component and runs it in its stages; the reference stays valid.
  virtual WorldComponent& addComponent(std::unique_ptr<WorldComponent> component) = 0;

 protected:
  // A world moves (a translator returns it); only a World copies or moves its interface.
  ComponentWorld() = default;
  ComponentWorld(const ComponentWorld&) = default;
  ComponentWorld(ComponentWorld&&) = default;
  ComponentWorld& operator=(const ComponentWorld&) = default;
  ComponentWorld& operator=(ComponentWorld&&) = default;
};

}  // namespace demlink::core
