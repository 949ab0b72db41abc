#pragma once
/// VTK XML output for ParaView: particles and triangle meshes as PolyData (.vtp)
/// and a time series as a ParaView collection (.pvd).
///
/// Why this shape: VTK XML is the one format ParaView, VisIt and most
/// post-processing scripts read without plug-ins, and PolyData with one vertex
/// cell per particle renders directly (Points / Point Gaussian representation,
/// or a Glyph filter scaled by "radius"). Two encodings:
///   - AppendedRaw (default): the XML header lists each DataArray with a byte
///     offset into one <AppendedData encoding="raw"> block after a '_' marker;
///     each block is a UInt64 byte count followed by the values in the machine's
///     byte order (declared in byte_order). Compact and exact, ~8 bytes a value.
///   - Ascii: values inline as text (shortest round-trip form), easy to diff.
/// The writer knows nothing of the scene or protobuf; it takes engine arrays.
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "demlink/core/math_types.hpp"
#include "demlink/core/particles/particle_arrays.hpp"

namespace demlink::core {

enum class VtkEncoding : std::uint8_t {
  AppendedRaw,  ///< binary block after the XML (compact, exact)
  Ascii,        ///< inline text
};

/// One frame of a .pvd time series.
struct PvdEntry {
  double time = 0.0;  ///< simulated time of the frame [s]
  std::string file;   ///< data file, relative to the .pvd's directory
};

/// Writes the particles as PolyData: points at the centres [m], one vertex cell
/// each, and point data "id" (UInt64), "radius" [m], "velocity" [m/s],
/// "angular_velocity" [rad/s], "force" [N] (contact force, gravity excluded) and
/// "material" (UInt32 index), and "clump_id" (UInt64: the id of the clump a sphere
/// belongs to, 0 for a free sphere). Throws std::runtime_error if the file cannot be written.
void writeParticlesVtp(const std::string& path, const ParticleArrays& particles,
                       VtkEncoding encoding = VtkEncoding::AppendedRaw);

/// Writes a triangle mesh as PolyData (vertices [m], one polygon per triangle).
/// Throws std::invalid_argument for a vertex index out of range and
/// std::runtime_error if the file cannot be written.
void writeMeshVtp(const std::string& path, std::span<const Vec3> vertices,
                  std::span<const std::array<std::uint32_t, 3>> triangles,
                  VtkEncoding encoding = VtkEncoding::AppendedRaw);

/// Writes a ParaView collection listing the frames in the given order.
/// Throws std::runtime_error if the file cannot be written.
void writePvd(const std::string& path, std::span<const PvdEntry> entries);

}  // namespace demlink::core
