#pragma once
/// Headless mode: runs a compiled scene to its end time with no remote
/// components, writing VTK frames, a .pvd index and summary.csv.
///
/// Order: initialise the world (time-step check, force kernel selection), print
/// the compile report (active stages, critical time step, dt as % of the limit),
/// then step, writing a frame every output.vtk_interval of simulated time (plus
/// the first and the last) and a progress line every progress_interval of wall
/// time. Output directory layout:
///   particles.pvd              time series of the particle frames (open in ParaView)
///   particles_000000.vtp ...   one PolyData file per frame
///   planes.vtp                 the plane walls as quads (only if the scene has planes)
///   summary.csv                one row per frame: time, particles, kinetic energy, ...
///   run_log.csv                configuration (at start) and timing (at the end) (run_log.hpp)
///   checkpoint_NNNNNN.bin      every output.checkpoint_interval; checkpoint_final.bin at the end
///   particles_final.csv        the final particles (particle_csv.hpp), loadable by a ParticleSystem
/// With run.restore_file set, the world continues from that checkpoint (same scene)
/// and the run goes on to end_time.
#include <cstdint>
#include <filesystem>
#include <functional>

#include "demlink/server/scene/scene_translator.hpp"

namespace demlink::server {

/// What a headless run did.
struct RunSummary {
  std::uint64_t steps = 0;               ///< time steps taken [-]
  std::size_t frames = 0;                ///< frames written (= rows of summary.csv) [-]
  std::size_t checkpoints = 0;           ///< checkpoint files written [-]
  std::size_t final_particles = 0;       ///< [-]
  double final_time = 0.0;               ///< [s]
  double final_kinetic_energy = 0.0;     ///< [J]
  double wall_seconds = 0.0;             ///< stepping and output, excluding initialisation [s]
  std::uint64_t bonds_created = 0;       ///< parallel bonds made during the run and before it [-]
  std::uint64_t bonds_broken = 0;        ///< of those, broken by the end [-]
  std::filesystem::path output_directory;
};

/// Sees the world after its initial state and after every step (the live view's hook,
/// LiveViewHub::offer); it must not change the world.
using StepObserver = std::function<void(const core::World&)>;

/// Runs the scene to scene.run.end_time. Throws core::InputError for problems
/// of the scene found at start-up (time step above the critical limit, missing
/// or unwritable output directory, end time shorter than a step) and
/// std::runtime_error if output cannot be written. `observer`, if set, sees every step.
RunSummary runHeadless(TranslatedScene& scene, const StepObserver& observer = {});

/// What runHeadless checks before its first step, without stepping or writing anything
/// (demlink-run --check): the world initialises (time step against the critical one) and
/// the run's intervals become steps. Throws core::InputError naming the field.
void checkHeadless(TranslatedScene& scene);

}  // namespace demlink::server
