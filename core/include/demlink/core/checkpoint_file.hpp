#pragma once
/// Checkpoint files: the complete state a time step depends on, so that a world
/// built from the same scene and restored from a checkpoint continues bit for
/// bit as if the run had never stopped (docs/state.md).
///
/// World::saveCheckpoint / World::restoreCheckpoint (core/src/world_checkpoint.cpp)
/// write and read the sections below in this order, each payload written and read
/// by its object (docs/state.md); this header has the file-level helpers, the
/// materials section and the particle-only reader used to load a saved particle set
/// into a different scene.
///
/// File layout (native byte order, checked on reading):
///   "DEMLCKPT"  u32 format version  u32 byte-order mark 0x01020304  u32 sizeof(double)  f64 -1.5
///   sections, each: 4-byte tag, u64 length, payload (state_stream.hpp):
///     SETT settings   MATL materials   CLOK step count, next id, tallies, pending slot map
///     PART particle columns   NBRL neighbour list   PLAN planes   MESH meshes
///     FRAM bounds and frame motion   CLMP clumps   COMP component states
///     END  (marks a complete file)
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "demlink/core/materials/material.hpp"
#include "demlink/core/particles/particle_arrays.hpp"

namespace demlink::core {

class World;
class StateWriter;
class StateReader;

inline constexpr char kCheckpointMagic[9] = "DEMLCKPT";
/// Bumped whenever a section changes; a file of another version is refused.
inline constexpr std::uint32_t kCheckpointVersion = 3;
inline constexpr std::uint32_t kCheckpointByteOrderMark = 0x01020304u;

/// The name of a run's checkpoint number `number`: "checkpoint_NNNNNN.bin" (six digits
/// at least), and the one of its end: "checkpoint_final.bin".
[[nodiscard]] std::string checkpointFileName(std::uint64_t number);
inline constexpr char kFinalCheckpointFileName[] = "checkpoint_final.bin";

/// Writes world.saveCheckpoint to `path` (writeCheckpointBytes). Throws
/// std::runtime_error if the file cannot be written. Defined with World's checkpoint.
void writeCheckpointFile(const World& world, const std::filesystem::path& path);

/// Reads `path` and restores it into `world` (World::restoreCheckpoint). Throws
/// InputError naming the file and section. Defined with World's checkpoint.
void restoreCheckpointFile(World& world, const std::filesystem::path& path);

/// Writes `bytes` to `path` via a temporary file renamed into place, so a crash never
/// leaves a half-written checkpoint under the final name. Throws std::runtime_error
/// if the file cannot be written.
void writeCheckpointBytes(const std::filesystem::path& path, const std::string& bytes);

/// The file header: magic, version, byte-order mark, double format.
void writeCheckpointHeader(StateWriter& out);
/// Checks magic, version, byte order and float format; leaves `in` at the first section.
void readCheckpointHeader(StateReader& in);
/// Section MATL: the materials, in index order.
void saveMaterials(StateWriter& out, const std::vector<Material>& materials);
/// Reads section MATL: the names, and (if `properties`) the materials appended to it.
[[nodiscard]] std::vector<std::string> readMaterialNames(StateReader in, std::vector<Material>* properties);

/// The particles of a checkpoint, with material names instead of indices.
struct CheckpointParticles {
  std::vector<std::string> material_names;  ///< of the checkpoint's scene, by index
  std::vector<ParticleSpec> particles;      ///< material = index into material_names
  std::vector<std::uint64_t> ids;           ///< stable ids in the checkpoint
  double time = 0.0;                        ///< simulated time of the checkpoint [s]
};

/// Reads only the particles (positions, velocities, angular velocities, radii,
/// materials, ids) of a checkpoint file. Throws InputError naming the file and section.
[[nodiscard]] CheckpointParticles readCheckpointParticles(const std::filesystem::path& path);

/// Whole file into memory; throws InputError (field = path) if it cannot be read.
[[nodiscard]] std::string readCheckpointBytes(const std::filesystem::path& path);

}  // namespace demlink::core
