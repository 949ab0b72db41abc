#pragma once
/// The particle-set CSV: what a headless run writes at its end
/// (particles_final.csv) and what a ParticleSystem component loads.
///
///   id,x,y,z,vx,vy,vz,radius,material
///   1,0.0045,0.0045,0.0035,0,0,-0.1,0.002,beads
///
/// id a non-negative integer [-], centre x y z [m], velocity vx vy vz [m/s],
/// radius [m] (> 0), material the name of a material of the scene. Numbers are
/// written with 17 significant digits, so a write/read round trip reproduces
/// every double exactly. Blank lines are ignored; everything else is checked and
/// an error names "<file>:line <n>" and the column, never the line's text.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/world.hpp"

namespace demlink::server {

struct ParticleCsvRecord {
  std::uint64_t id = 0;                      ///< the file's id [-]
  core::Vec3 position = core::Vec3::Zero();  ///< [m]
  core::Vec3 velocity = core::Vec3::Zero();  ///< [m/s]
  double radius = 0.0;                       ///< [m]
  std::string material;                      ///< material name
  std::size_t line = 0;                      ///< 1-based line in the file
};

/// The header line (without the newline).
inline constexpr std::string_view kParticleCsvHeader = "id,x,y,z,vx,vy,vz,radius,material";

/// Parses CSV text; `sourceName` names it in errors. Throws core::InputError
/// for a wrong header, a malformed line, a repeated id or no particle at all.
[[nodiscard]] std::vector<ParticleCsvRecord> parseParticleCsv(std::string_view text, const std::string& sourceName);

/// Reads a CSV file (errors as parseParticleCsv, or "<path>" if unreadable).
[[nodiscard]] std::vector<ParticleCsvRecord> readParticleCsv(const std::filesystem::path& path);

/// Writes the world's particles in id order. Throws std::runtime_error if the
/// file cannot be written or a material name cannot be written to CSV.
void writeParticleCsv(const core::World& world, const std::filesystem::path& path);

}  // namespace demlink::server
