/// The rows of the step table: text for the report and the docs next to the
/// condition that selects each stage, so the two cannot drift apart.
#include "demlink/core/step/stage_table.hpp"

namespace demlink::core {
namespace {

using F = SceneFeatures;

constexpr std::array<StageInfo, kStageCount> kTable{{
    {Stage::kMeshMotion, "mesh_motion", false, false,
     "collision windows at the step's end; meshes with a twist advance by dt; notes whether a colliding mesh "
     "moved more than skin/2 since the last neighbour build",
     "mesh twists and collision windows, time", "mesh poses, colliding flags", "scene has meshes",
     [](const F& f) { return f.meshes; }},
    {Stage::kInsertRemove, "insert_remove", false, false,
     "components: sources insert, sinks remove (reported as `<kind>:<name>`)",
     "regions, positions, time at the step's start", "particles, slots, tallies",
     "a component declares insert/remove", [](const F& f) { return f.insert_remove_components; }},
    {Stage::kBoundsRemoval, "bounds_removal", false, false, "remove the particles whose centre left the fixed box",
     "positions", "slots (compaction), removal tally", "scene has fixed bounds",
     [](const F& f) { return f.fixed_bounds; }},
    {Stage::kGrowingBounds, "growing_bounds", false, false,
     "remove the particles whose centre left the limit box; grow the box around the others", "positions, radii",
     "slots (compaction), removal tally, current bounds", "scene has growing bounds",
     [](const F& f) { return f.growing_bounds; }},
    {Stage::kVelocityVerlet, "velocity_verlet", false, true,
     "first half kick v += a dt/2 and drift x += v dt (with the fictitious forces when the frame moves)",
     "forces, velocities, gravity, frame motion", "velocities, positions", "integrator is velocity_verlet",
     [](const F& f) { return f.velocity_verlet; }},
    {Stage::kExplicitEuler, "explicit_euler", false, false,
     "x += v dt, v += a dt with the old a (with the fictitious forces when the frame moves)",
     "forces, velocities, gravity, frame motion", "velocities, positions", "integrator is explicit_euler",
     [](const F& f) { return !f.velocity_verlet; }},
    {Stage::kMovingFrame, "moving_frame", false, false,
     "the frame's angular velocity advances, Omega += alpha dt (Omega at the step's end for the second half kick)",
     "frame motion", "frame angular velocity", "frame is not inertial", [](const F& f) { return f.frame_moving; }},
    {Stage::kClumpRigidBodies, "clump_rigid_bodies", false, false,
     "clump bodies: half kick and drift (Euler: drift, then a whole kick); members placed from their body",
     "body forces, gravity, frame linear acceleration", "body state, member positions and velocities",
     "scene has clump templates", [](const F& f) { return f.clumps; }},
    {Stage::kDeformableMotion, "deformable_motion", false, false,
     "deformable bodies' first half: nodes move to the step's end (mass-spring: half kick and drift; driven "
     "nodes follow their pose), surfaces written; notes whether a surface moved more than skin/2 since the last "
     "neighbour build (reported as `<kind>:<name>`)",
     "node forces, gravity, driving poses", "node positions and velocities, surfaces", "scene has deformable bodies",
     [](const F& f) { return f.deformables; }},
    {Stage::kNeighbourList, "neighbour_list", false, true,
     "rebuild (periodic cell sort, Verlet list, plane, mesh and deformable-surface near lists; histories "
     "carried) when slots changed, a colliding mesh or a deformable surface moved far, a surface triangle lost "
     "its support, or a contact may have been missed: a pair or plane contact whose relative displacement closed the "
     "skin (rebuild_guard.hpp), or, in scenes with meshes or deformable bodies, a particle moved more than skin/2",
     "positions, mesh poses, deformable surfaces", "neighbour and near lists, slot order", "always",
     [](const F&) { return true; }},
    {Stage::kForces, "forces", false, true,
     "clear forces and torques, then the passes below in one call chosen at initialisation (law, rolling, "
     "cohesion and recording fixed)",
     "positions, velocities, contact histories", "forces, torques, contact histories", "always",
     [](const F&) { return true; }},
    {Stage::kParticleContacts, "particle_contacts:<law>", true, true,
     "particle pairs, threaded by row chunks whose buffers are summed in chunk order", "neighbour list, pair table",
     "forces, torques, pair histories", "always", [](const F&) { return true; }},
    {Stage::kPlaneContacts, "plane_contacts", true, true, "particles on planes", "plane near lists",
     "forces, torques, plane wrenches", "scene has planes", [](const F& f) { return f.planes; }},
    {Stage::kMeshContacts, "mesh_contacts", true, false,
     "particles on the meshes inside their collision window (wrenches of the others cleared)", "mesh near lists",
     "forces, torques, mesh wrenches", "scene has meshes", [](const F& f) { return f.meshes; }},
    {Stage::kDeformableContacts, "deformable_contacts", true, false,
     "particles on the active triangles of each deformable surface (the mesh contact, with the surface's "
     "velocity and forces spread barycentrically to its nodes)",
     "deformable near lists, surfaces", "forces, torques, surface node forces", "scene has deformable bodies",
     [](const F& f) { return f.deformables; }},
    {Stage::kRollingResistance, "rolling_resistance", true, true, "rolling-resistance torque in every contact pass",
     "pair table", "torques", "a material pair has rolling friction", [](const F& f) { return f.rolling; }},
    {Stage::kCohesion, "cohesion", true, true,
     "cohesive attraction k_c A in every contact pass, A the area of the overlap's contact circle",
     "pair table", "forces, torques", "a material pair has cohesion", [](const F& f) { return f.cohesion; }},
    {Stage::kContactRecording, "contact_recording", true, true,
     "every contact pass records its contacts on the contact output's steps, and adds mesh contacts into "
     "per-triangle loads and their time integrals every step",
     "contact forces, slip velocities", "contact records, triangle loads", "contact output is requested",
     [](const F& f) { return f.contact_recording; }},
    {Stage::kParallelBonds, "parallel_bonds", false, false,
     "intact bonds advance by the step's relative motion, add their force and moments, and break at their "
     "strength; then the rules whose creation time has come bond their pairs",
     "positions, velocities, spins, bond states", "forces, torques, bond states", "scene declares parallel bonds",
     [](const F& f) { return f.parallel_bonds; }},
    {Stage::kDeformableForces, "deformable_forces", false, false,
     "deformable bodies' second half: internal forces with this step's contact forces (mass-spring: springs, "
     "tearing, second half kick; FEM: the load of the next solve), reactions (reported as `<kind>:<name>`)",
     "surface node forces, node state", "node velocities and forces, broken springs, reactions",
     "scene has deformable bodies", [](const F& f) { return f.deformables; }},
    {Stage::kClumpForceSum, "clump_force_sum", false, false, "member forces and torques summed on each clump body",
     "member forces and torques", "body force and torque", "scene has clump templates",
     [](const F& f) { return f.clumps; }},
    {Stage::kSecondHalfKick, "second_half_kick", false, true,
     "v += a dt/2 and the spin likewise (with the fictitious forces when the frame moves)",
     "forces, velocities, gravity, frame motion", "velocities", "integrator is velocity_verlet",
     [](const F& f) { return f.velocity_verlet; }},
    {Stage::kClumpHalfKick, "clump_half_kick", false, false, "clump bodies' second half kick; member velocities",
     "body forces", "body momenta, member velocities", "integrator is velocity_verlet and scene has clump templates",
     [](const F& f) { return f.velocity_verlet && f.clumps; }},
    {Stage::kAdvanceClock, "advance_clock", false, true, "step counter + 1: the world's time is the step's end",
     "step counter", "step counter", "always", [](const F&) { return true; }},
    {Stage::kObserve, "observe", false, false,
     "components: region and flow sensors, trackers, sinks' tallies (reported as `<kind>:<name>`)",
     "positions, velocities, meshes, time at the step's end", "readings, CSV rows", "a component declares observe",
     [](const F& f) { return f.observe_components; }},
    {Stage::kWatchdog, "watchdog", false, true,
     "every `every_steps` steps: non-finite values, overlaps, energy growth, speeds against the validated impact "
     "speed; a failed check stops the run or warns once (policy)",
     "positions, velocities, forces, neighbour and plane near lists", "watchdog memory, warnings",
     "watchdog.every_steps > 0 (default 100)", [](const F& f) { return f.watchdog; }},
}};

// The table is indexed by Stage: each row must sit at its own enumerator.
constexpr bool rowsInEnumOrder() {
  for (std::size_t k = 0; k < kTable.size(); ++k) {
    if (static_cast<std::size_t>(kTable[k].stage) != k) return false;
  }
  return true;
}
static_assert(rowsInEnumOrder(), "stage table rows must follow the Stage enum");

}  // namespace

const std::array<StageInfo, kStageCount>& stageTable() { return kTable; }

const StageInfo& stageInfo(Stage stage) { return kTable[static_cast<std::size_t>(stage)]; }

std::vector<Stage> selectStages(const SceneFeatures& features) {
  std::vector<Stage> stages;
  for (const StageInfo& row : kTable) {
    if (row.runs(features)) stages.push_back(row.stage);
  }
  return stages;
}

bool kickMayBeOwed(const std::vector<Stage>& stages) {
  for (const Stage stage : stages) {
    if (!stageInfo(stage).kick_may_be_owed) return false;
  }
  return true;
}

std::string stageTableMarkdown() {
  std::string text = "| stage | does | reads | writes | runs when | kick may be owed |\n|---|---|---|---|---|---|\n";
  for (const StageInfo& row : kTable) {
    text += row.pass ? "| ↳ `" : "| `";
    text += row.name;
    text += "` |";
    for (const std::string_view cell : {row.does, row.reads, row.writes, row.runs_when}) {
      text += ' ';
      text += cell;
      text += " |";
    }
    text += row.kick_may_be_owed ? " yes |" : " no |";
    text += '\n';
  }
  return text;
}

}  // namespace demlink::core
