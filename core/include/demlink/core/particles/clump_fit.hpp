#pragma once
/// A multisphere clump template that approximates a solid given as a closed triangle mesh
/// (docs/clumps.md, "Fitting a template to an STL").
///
/// Method: spheres are centred near the solid's medial axis, deepest first.
///  1. The solid is sampled on a grid (solid_samples.hpp): inside flags and an approximate
///     depth per sample.
///  2. Greedy: the candidates are the samples no sphere covers yet within one grid spacing
///     of the largest depth (spread evenly over them when there are more than the distance
///     budget allows). Their exact distance to the surface is the radius of the sphere each
///     could hold (inscribed: it touches the surface and never crosses it). Among those
///     within half a spacing of the largest radius, the sphere goes to the candidate that
///     covers the most uncovered samples (ties: for the first sphere the one nearest the
///     centroid of the solid's samples, later the one farthest from every placed centre),
///     its centre then moved by at most one spacing to where it is farthest from
///     the surface. Every sample inside it is marked covered. Repeat.
///  3. Optionally all radii are scaled by one factor so the union of the spheres (overlaps
///     counted once, unionMoments) has the solid's volume: inscribed spheres always miss
///     volume (the corners and the gaps between spheres), and the scaled spheres trade a
///     little protrusion for the right mass.
/// Deterministic: no random numbers; ties go to the lower sample index.
#include <cstddef>
#include <vector>

#include "demlink/core/base/math_types.hpp"
#include "demlink/core/particles/clump_template.hpp"
#include "demlink/core/geometry/solid_mass_properties.hpp"
#include "demlink/core/geometry/solid_samples.hpp"
#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::core {

/// Most triangles a mesh to be fitted may have (each placed sphere costs at least
/// kMinClumpFitCandidates exact distance queries over every triangle).
inline constexpr std::size_t kMaxClumpFitTriangles = 200000;
/// Grid samples along the solid's longest side: the bounds of ClumpFitOptions::grid_cells.
inline constexpr std::size_t kMinClumpFitGridCells = 8;
inline constexpr std::size_t kMaxClumpFitGridCells = 200;
/// Exact point-triangle distances one placed sphere may cost: the candidate centres per
/// sphere are this over the triangle count, within [kMinClumpFitCandidates, kMaxClumpFitCandidates].
inline constexpr std::size_t kClumpFitDistanceBudget = 4'000'000;
inline constexpr std::size_t kMinClumpFitCandidates = 16;
inline constexpr std::size_t kMaxClumpFitCandidates = 1024;

/// Spheres inscribed in the solid by the greedy of step 2, in the mesh's frame. Fewer than
/// `count` when every inside sample is covered first (a finer grid then gives more).
[[nodiscard]] std::vector<ClumpSphere> inscribedSpheres(const StlMesh& mesh, const SolidSamples& samples,
                                                        std::size_t count);

/// Factor applied to every radius so the union of `spheres` has `volume` [m^3] (step 3),
/// to a relative 1e-8 of the union volume at a 64-direction quadrature.
[[nodiscard]] double volumeMatchingScale(const std::vector<ClumpSphere>& spheres, double volume);

/// How far a clump template's mass properties are from the solid's (both per unit density).
struct ClumpFitErrors {
  double volume = 0.0;              ///< (V_clump - V_solid) / V_solid [-]
  double centre_of_mass = 0.0;      ///< |c_clump - c_solid| / V_solid^(1/3) [-]
  Vec3 principal_moments = Vec3::Zero();  ///< (I_clump - I_solid) / I_solid per principal moment, ascending [-]
  double bounding_radius = 0.0;     ///< (R_clump - R_solid) / R_solid, R from the centre of mass [-]

  /// The largest of |volume|, centre_of_mass and |principal_moments|.
  [[nodiscard]] double largest() const;
};

/// `clump` must be in the solid's frame (offsets as the mesh's coordinates).
[[nodiscard]] ClumpFitErrors compareWithSolid(const ClumpTemplate& clump, const SolidMassProperties& solid);

}  // namespace demlink::core
