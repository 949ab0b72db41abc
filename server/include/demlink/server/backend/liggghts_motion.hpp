#pragma once
/// A moving mesh as LIGGGHTS-PUBLIC commands (fix move/mesh), kept free of LIGGGHTS and MPI
/// like liggghts_script.hpp.
///
/// Our engine moves a mesh at a constant twist during an interval (velocity u of its
/// reference point P, angular velocity w) exactly: P moves by u t and the mesh turns by
/// w t about the world axis through the moving P (MeshBody::advance). LIGGGHTS gets the
/// same motion from four move/mesh fixes that stay for the whole run, so a new twist needs
/// no set-up (neighbour lists of particles and meshes): `linear/variable` at u, then
/// `rotate/variable` about the world x, y and z axes through P at rates (a, b, c) / dt.
/// LIGGGHTS applies superposed fixes in creation order each step, each carrying the
/// reference points of the later ones along ("the origin of the rotation axis would be in
/// local reference frame", LIGGGHTS documentation of fix move/mesh), so the rotations turn
/// about the moving P; their axes stay fixed in the world. One step therefore turns the
/// mesh by Rz(c) Ry(b) Rx(a), and (a, b, c) are the z-y-x angles of exp(dt [w]x): the
/// step's rotation exactly, whatever w's direction. The wall velocity the particles see is
/// u + (a, b, c) / dt x (x - P), which differs from ours, u + w x (x - P), by O(dt |w|^2).
///
/// The fixes read equal-style variables that the backend sets each interval. LIGGGHTS
/// 3.8's fixes keep a variable's index, and re-defining an equal-style variable removes it
/// and appends it at the end, shifting the ones after it; so each fix reads a variable
/// defined once (liggghtsMeshMotionSetup, before any other variable) whose formula names
/// a value variable (liggghtsMeshTwist re-defines those), looked up by name on each use.
#include <cstddef>
#include <string>
#include <vector>

#include "demlink/core/base/math_types.hpp"

namespace demlink::server {

/// One LIGGGHTS fix: its id (for unfix) and the command that creates it.
struct LiggghtsFix {
  std::string id;
  std::string command;
};

/// The per-step rotation angles (a, b, c) [rad] about the world x, y, z axes, applied in
/// that order, whose product Rz(c) Ry(b) Rx(a) is the rotation by `angular` [rad/s] over
/// `dt` [s]. Exact for any |angular| dt < pi / 2.
[[nodiscard]] core::Vec3 liggghtsStepAngles(const core::Vec3& angular, double dt);

/// The variables the move fixes of mesh `mesh` read, all zero: the six fix-facing
/// variables (each naming its value variable), then the six value variables. Give them
/// for every mesh before any other variable is defined.
[[nodiscard]] std::vector<std::string> liggghtsMeshMotionSetup(std::size_t mesh);

/// The fixes that move mesh `mesh` (its fix mesh/surface/stress liggghtsMeshFix(mesh)), in
/// creation order, rotating about its reference point `reference` [m] as it is when they
/// are created; they move it at the twist the value variables hold.
[[nodiscard]] std::vector<LiggghtsFix> liggghtsMeshMotionFixes(std::size_t mesh, const core::Vec3& reference);

/// The commands that set mesh `mesh`'s value variables to the twist `linear` [m/s] of its
/// reference point and `angular` [rad/s] (world frame) for steps of `dt` [s].
[[nodiscard]] std::vector<std::string> liggghtsMeshTwist(std::size_t mesh, const core::Vec3& linear,
                                                         const core::Vec3& angular, double dt);

}  // namespace demlink::server
