#pragma once
/// A snapshot as the compact binary frame the page draws (one WebSocket binary message).
///
/// Layout (little-endian; every section starts on a 4-byte boundary so the page reads it
/// with typed arrays, no copying):
///   header, kFrameHeaderBytes:
///     0 u32 magic "DLVF"        4 u32 version (2)
///     8 f64 time [s]           16 f64 step           24 f64 real-time factor
///    32 f64 steps per second   40 f64 particle mass  48 f64 inserted mass
///    56 f64 removed mass       64 f64 initial mass [kg]
///    72 u32 particles in the world                    76 u32 particles in this frame (m)
///    80 f32[3] box lower [m]   92 f32[3] box upper [m]
///   104 f32 largest radius [m]  108 f32 colour minimum  112 f32 colour maximum
///   116 u32 colour field (ColourField)  120 u32 meshes  124 u32 surfaces  128 u32 regions
///   132 u32 frame index  136 u32 frame count (a recorded run; 0 live)  140 u32 reserved
///   positions: u16[3 m], each axis quantised over [box lower, box upper]
///   radii:     u16[m], quantised over [0, largest radius]
///   colours:   u16[m], quantised over [colour minimum, colour maximum]
///   meshes:    per mesh f32[7]: position, orientation (x, y, z, w)
///   regions:   per region u32 kind, f32[3] half size, f32[7] pose (ViewRegion)
///   surfaces:  per surface u32 nodes, u32 triangles, u32 springs, f32[3 nodes],
///              u8[triangles] active, u8[springs] intact (the scene lists the springs)
/// Quantising to 16 bits puts a particle within (upper - lower) / 131070 of its place on
/// each axis: a 10 m domain draws to 0.08 mm.
///
/// Fewer particles than the world holds (the page asks for at most `max_particles`): the
/// frame carries the `max_particles` whose ids hash lowest (subsetRank), so the subset is
/// stable while particles move, and a smaller subset is part of any larger one.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "demlink/server/view/view_snapshot.hpp"

namespace demlink::server {

inline constexpr std::uint32_t kFrameMagic = 0x46564C44;  // "DLVF" in little-endian byte order
inline constexpr std::uint32_t kFrameVersion = 2;
inline constexpr std::size_t kFrameHeaderBytes = 144;

/// What one page asked for.
struct FrameRequest {
  std::size_t max_particles = 1'000'000;
  ColourField colour = ColourField::kSpeed;
  std::uint32_t frame_index = 0;  ///< recorded runs: which frame of how many
  std::uint32_t frame_count = 0;
};

/// The rank of an id in the stable subset (a 32-bit mix of the id: lower ranks first).
[[nodiscard]] std::uint32_t subsetRank(std::uint64_t id);

/// Slots of the at most `maxParticles` particles with the lowest subsetRank (ties: lower
/// id), in ascending slot order; all slots when there are no more than `maxParticles`.
/// `slots` and `ranks` are reused buffers.
void chooseSubset(std::span<const std::uint64_t> ids, std::size_t maxParticles, std::vector<std::uint32_t>& slots,
                  std::vector<std::uint64_t>& ranks);

/// value in [lower, upper] to 0..65535 (clamped; a degenerate range gives 0).
[[nodiscard]] std::uint16_t quantise(double value, double lower, double upper);

/// Reused buffers of one connection's encoder.
struct FrameScratch {
  std::vector<std::uint32_t> slots;
  std::vector<std::uint64_t> ranks;
};

/// Writes the frame of `snapshot` for `request` into `out` (resized; its capacity is reused).
void encodeFrame(const ViewSnapshot& snapshot, const FrameRequest& request, FrameScratch& scratch,
                 std::vector<std::uint8_t>& out);

}  // namespace demlink::server
