#pragma once
/// Limits on what a scene file or a client may ask for, each refused with an InputError
/// naming the field (the table "Limits and defaults" in docs/server.md lists them).
#include <cstddef>
#include <cstdint>
#include <string>

namespace demlink::core {
class World;
}

namespace demlink::server {

/// Longest wall-clock wait the server accepts or schedules (client timeout, quiet
/// period) [s]: one week. Longer waits are clamped to it when a deadline is computed.
inline constexpr double kMaxWaitSeconds = 7.0 * 24.0 * 3600.0;

/// Memory one sphere costs a running world [bytes]: its particle columns, the Verlet list
/// with carried contact histories, the cell grid, output buffers and the translator's
/// copy while the scene is built. Measured: the peak resident memory (VmHWM) of
/// demlink-run grows by 1,046 bytes per sphere from an 8,000- to a 125,000-sphere
/// lattice (spacing 2.1 r, six neighbours each, final checkpoint and CSV written);
/// rounded up for denser beds (docs/server.md, "Limits and defaults").
inline constexpr std::uint64_t kBytesPerParticle = 1280;

/// Memory the particles of one scene may take [bytes]: half of the smaller of the
/// machine's physical memory and the process's address-space limit (RLIMIT_AS).
[[nodiscard]] std::uint64_t particleMemoryBudget();

/// Throws core::InputError naming `field` (with `value`) when `particles` spheres would
/// need more than particleMemoryBudget() at kBytesPerParticle: refused before anything
/// is allocated.
void requireParticleMemory(const std::string& field, const std::string& value, std::uint64_t particles);

/// Components that each keep an output file open while a world runs (sensors, sinks,
/// trackers: their CSVs) [-]: far above any scene's need, far below the process's file
/// limit (1,024 by default) shared by every simulation of a server.
inline constexpr std::size_t kMaxFileComponents = 256;

/// Throws core::InputError naming the first component past kMaxFileComponents.
void requireOutputFileCount(const core::World& world);

}  // namespace demlink::server
