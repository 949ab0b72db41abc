#pragma once
/// A compiled scene as LIGGGHTS-PUBLIC input: what the LIGGGHTS backend feeds libliggghts
/// (liggghts_backend.hpp), kept free of LIGGGHTS and MPI so it builds and is tested
/// everywhere. docs/scale-out.md has the mapping table and the refusals.
///
/// Mapping, for a world after World::initialize() (which ran our critical time-step check):
///   material k            atom type k + 1; Young's modulus and Poisson ratio per type
///                         (a rigid material: 1e6 x the stiffest modulus, so the particle
///                         alone sets the contact stiffness as in our engine)
///   pair (a, b)           restitution and friction per type pair from our pair table
///                         (mixing and material_pair overrides included); the restitution
///                         is the one LIGGGHTS must be given for its damping to equal ours
///                         (liggghtsRestitution); limitForce on in pair_style gran and
///                         every wall/gran, as our normal force, clamped at zero, never pulls
///   rolling friction      pair (a, b)'s mu_r: coefficientRollingFriction per type pair,
///                         rolling_friction cdt in pair_style gran and every wall/gran
///   time step, gravity    timestep, fix gravity
///   skin                  neighbor <skin> bin, neigh_modify delay 0
///   bounds                the box of read_data, boundary f f f (particles leaving it are lost)
///   plane                 fix wall/gran ... primitive type <material> x|y|zplane (axis-aligned)
///   mesh_body, rigid_body, its world-frame triangles as an STL file, fix mesh/surface/stress
///   FIXED facet_body
///                         (type <material>, reference_point = the body's position), all
///                         meshes in one fix wall/gran ... mesh; a moving mesh gets fix
///                         move/mesh from the backend (liggghts_motion.hpp)
///   particles             read_data: id = slot + 1, type, diameter, density, x; velocities
///                         (a pit_generator's bed is settled by our engine before the run and
///                         arrives here as initial particles)
#include <string>
#include <vector>

#include "demlink/core/world.hpp"
#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// The restitution to give LIGGGHTS's Hertz law (gamma_n = -2 sqrt(5/6) beta sqrt(S_n m*),
/// beta = ln e / sqrt(ln^2 e + pi^2)) so that its damping equals ours, gamma_n =
/// normalDamping sqrt(S_n m*). Both laws damp the tangential spring the same way from it.
/// Ours is calibrated to deliver the requested restitution; LIGGGHTS's formula, taken from
/// the linear law, does not for Hertz, so the value differs from the requested one. Equal
/// damping delivers equal restitution only if LIGGGHTS clamps its normal force at zero as
/// we do (limitForce on, which liggghtsCommands gives).
/// Throws core::InputError naming `field` if no restitution in (0, 1] gives that damping.
[[nodiscard]] double liggghtsRestitution(double normalDamping, const std::string& field);

/// Refuses, naming the component and the reason, what the LIGGGHTS backend cannot run:
/// component kinds it does not map (clumps, deformable bodies, trackers), facet bodies
/// that are not FIXED or have a collision window, pit generators of clumps, a moving
/// frame, and in the compiled world the linear law, explicit Euler,
/// cohesion, missing or growing bounds and
/// planes that are not axis-aligned. Throws core::InputError.
void requireLiggghtsCompatible(const v1::Scene& scene, const core::World& world);

/// The LIGGGHTS read_data file of the world's particles.
[[nodiscard]] std::string liggghtsDataFile(const core::World& world);

/// The world-frame triangles of `mesh` as an ASCII STL file.
[[nodiscard]] std::string liggghtsStl(const core::MeshBody& mesh);

/// The id of mesh `mesh`'s fix mesh/surface/stress (its global vector: force on the mesh
/// [N], then torque about the reference point [N m]).
[[nodiscard]] std::string liggghtsMeshFix(std::size_t mesh);

/// The commands that set up the run, in order: read_data reads `dataFile`, mesh k's
/// fix reads meshFiles[k] (one per world mesh). With `restartFile`, read_restart reads the
/// atoms (and the per-atom state of the fixes and pair style: contact histories) from it
/// instead, and every setting and fix is given again after it.
[[nodiscard]] std::vector<std::string> liggghtsCommands(const core::World& world, const std::string& dataFile,
                                                        const std::vector<std::string>& meshFiles = {},
                                                        const std::string& restartFile = {});

}  // namespace demlink::server
