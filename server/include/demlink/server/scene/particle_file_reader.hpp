#pragma once
/// Reader for particle text files: one sphere per line, "id x y z r" (id a
/// non-negative integer [-], centre x y z [m], radius r [m]), separated by spaces
/// or tabs; blank lines and everything after '#' are ignored. This is the format
/// the deposition benchmark's gen_init.py writes (init_N.txt), so DEMLink, LIGGGHTS
/// and LAMMPS can start from the same spheres.
///
/// Every malformed line is an error naming "<file>:line <n>" (too few or too many
/// columns, a value that is not a number, NaN or infinity, radius <= 0, a
/// repeated id), never a silently skipped sphere. Errors name the file, the line and the
/// column, never the line's text (a file named by a client must not leak into its error).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "demlink/core/base/math_types.hpp"

namespace demlink::server {

struct ParticleRecord {
  std::uint64_t id = 0;                      ///< the file's id [-]
  core::Vec3 position = core::Vec3::Zero();  ///< [m]
  double radius = 0.0;                       ///< [m]
  std::size_t line = 0;                      ///< 1-based line in the file
};

/// Reads a particle file. Throws core::InputError (field "<path>") if it cannot
/// be read or holds no sphere, and (field "<path>:line <n>") for a malformed line.
[[nodiscard]] std::vector<ParticleRecord> readParticleFile(const std::string& path);

/// Parses particle text already in memory; `sourceName` replaces the path in errors.
[[nodiscard]] std::vector<ParticleRecord> parseParticleText(std::string_view text, const std::string& sourceName);

}  // namespace demlink::server
