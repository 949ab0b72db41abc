#pragma once
/// VTK XML output for ParaView: particles, triangle meshes and deformable surfaces as
/// PolyData (.vtp), FEM volumes as UnstructuredGrid (.vtu) and a time series as a
/// ParaView collection (.pvd).
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
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/particles/particle_arrays.hpp"

#include "demlink/core/bonds/bond_set.hpp"
#include "demlink/core/contact/contact_record.hpp"

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

/// One frame of a deformable body's surface (mass-spring or the boundary of an FEM body).
struct DeformableFrame {
  std::span<const Vec3> positions;      ///< nodes [m]
  std::span<const Vec3> displacements;  ///< from the initial configuration [m]
  std::span<const Vec3> velocities;     ///< [m/s]
  std::span<const std::array<std::uint32_t, 2>> springs;  ///< node pairs (none for FEM)
  std::span<const char> spring_intact;  ///< per spring: 1 intact, 0 broken
  std::span<const std::array<std::uint32_t, 3>> triangles;
  std::span<const char> triangle_active;  ///< per triangle: 1 takes part in contacts, 0 lost its support
};

/// Writes a deformable surface as PolyData: the nodes with point data "displacement" [m]
/// and "velocity" [m/s]; one line cell per spring, then one polygon per triangle; cell
/// data "intact" (UInt8: 1 an intact spring / active triangle, 0 a broken spring /
/// inactive triangle; threshold it at 1 to hide the tears) and "cell_kind" (UInt8: 0
/// spring, 1 triangle). Throws std::invalid_argument for mismatched sizes or an index out
/// of range, std::runtime_error if the file cannot be written.
void writeDeformableVtp(const std::string& path, const DeformableFrame& frame,
                        VtkEncoding encoding = VtkEncoding::AppendedRaw);

/// Writes tetrahedra (4 or 10 nodes each, VTK node order) as an UnstructuredGrid (.vtu):
/// nodes [m] with point data "displacement" [m] and "velocity" [m/s], cell data
/// "von_mises_stress" [Pa]. Throws as writeDeformableVtp.
void writeTetrahedraVtu(const std::string& path, std::span<const Vec3> positions, std::span<const Vec3> displacements,
                        std::span<const Vec3> velocities, std::span<const std::vector<std::uint32_t>> elements,
                        std::span<const double> vonMises, VtkEncoding encoding = VtkEncoding::AppendedRaw);

/// Writes contacts as a force network (PolyData): per contact one line from the centre
/// of particle a to the centre of particle b, or to the contact point on a wall, with
/// cell data (conventions in contact_record.hpp) "normal_force" and "tangential_force"
/// (vectors on a [N]), "force_normal_component" (F_n [N], negative when cohesion
/// pulls), "overlap" [m], "contact_point" [m], "normal" [-], "kind" (UInt8:
/// ContactKind), "particle" and "other" (UInt64: ids or wall index) and "triangle"
/// (UInt32). Throws std::runtime_error if the file cannot be written.
void writeContactsVtp(const std::string& path, std::span<const ContactRecord> contacts,
                      VtkEncoding encoding = VtkEncoding::AppendedRaw);

/// Writes the bond network (PolyData): per bond, broken ones included, one line between
/// its particles' centres, with cell data "normal_force" (Fn [N], tension positive),
/// "shear_force" (Fs on the first particle [N], vector), "twisting_moment" [N m],
/// "bending_moment" [N m] (vector), "tensile_stress" and "shear_stress" (the largest on
/// the bond's rim [Pa]), "intact" (UInt8: 1 intact, 0 broken) and "particle_a",
/// "particle_b" (UInt64 ids). Throws std::runtime_error if the file cannot be written.
void writeBondsVtp(const std::string& path, const BondSet& bonds, const ParticleArrays& particles,
                   VtkEncoding encoding = VtkEncoding::AppendedRaw);

/// Writes triangle meshes (as writeMeshVtp) with per-triangle loads as cell data
/// (TriangleLoad, contact_record.hpp): "load_force" [N], "normal_force" [N],
/// "tangential_force" [N], "pressure" (normal_force / triangle area [Pa]),
/// "normal_impulse" and "tangential_impulse" [N s], "archard_work" [N m] and
/// "friction_work" [J]. `loads` holds one entry per triangle, or is empty (zeros).
/// Throws std::invalid_argument for another size or an index out of range.
void writeMeshLoadsVtp(const std::string& path, std::span<const Vec3> vertices,
                       std::span<const std::array<std::uint32_t, 3>> triangles, std::span<const TriangleLoad> loads,
                       VtkEncoding encoding = VtkEncoding::AppendedRaw);

/// Writes contacts as CSV, one row per contact (columns in contactsCsvColumns()).
/// Throws std::runtime_error if the file cannot be written.
void writeContactsCsv(const std::string& path, std::span<const ContactRecord> contacts);
/// The header of writeContactsCsv, with units.
[[nodiscard]] const std::vector<std::string>& contactsCsvColumns();

/// Writes a ParaView collection listing the frames in the given order.
/// Throws std::runtime_error if the file cannot be written.
void writePvd(const std::string& path, std::span<const PvdEntry> entries);

}  // namespace demlink::core
