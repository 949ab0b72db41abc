/// demlink-run: headless mode from the command line.
///
///   demlink-run <scene.json> [--output DIR] [--end-time T] [--restore FILE] [--overwrite] [--quiet]
///               [--backend native|liggghts] [--view ADDR:PORT [--view-linger S] [--pace X]
///               [--view-max-connections N] [--view-max-rate R] [--view-max-bytes-per-second B]] [--token T]
///   mpirun -np N demlink-run <scene.json> --backend liggghts ...   (docs/scale-out.md)
///   demlink-run --check <scene.json>
///   demlink-run --help | --version
///
/// Exit codes: 0 success; 2 bad input (scene, files, command line), printed as
/// "error: <field> = <value>: <reason>"; 1 any other failure (e.g. a disk full).
/// Command-line overrides are applied to the declarations before compilation,
/// so they are validated exactly like values from the scene file.
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "command_line_main.hpp"
#include "view_caps_command_line.hpp"
#include "demlink/cli/command_line.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/server/backend/liggghts_script.hpp"
#include "demlink/server/backend/simulation_backend.hpp"
#include "demlink/server/run/headless_runner.hpp"
#ifdef DEMLINK_HAS_LIGGGHTS
#include "demlink/server/backend/liggghts_backend.hpp"
#endif
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "demlink/server/view/live_view_hub.hpp"
#include "demlink/server/view/view_server.hpp"

namespace {

namespace cli = demlink::cli;

struct CommandLine {
  std::string scene;
  std::optional<std::string> output;
  std::optional<double> end_time;  ///< [s]
  std::optional<std::string> restore;
  bool overwrite = false;
  bool quiet = false;
  bool check = false;
  std::string backend = "native";
  std::optional<std::string> view;
  double view_linger = 0.0;  ///< [s]
  double pace = 0.0;         ///< most simulated seconds per wall second; 0: as fast as it goes
  std::optional<std::string> token;
  demlink::server::ViewServerOptions view_caps;  ///< the --view-max-* options
};

int run(int argc, char** argv) {
  CommandLine line;
  CLI::App app("Runs a scene headless: compiles it, steps it to its end time, writes its outputs.", "demlink-run");
  app.add_option("scene", line.scene, "scene file (JSON)")->required()->type_name("SCENE.json");
  cli::addText(app, "--output", line.output,
               "output directory (default: the scene's output.directory, else out/<scene name>)")
      ->type_name("DIR");
  cli::addNumber(app, "--end-time", line.end_time, {0.0, true}, "simulated end time [s], overrides simulation_box.end_time")
      ->type_name("T");
  cli::addText(app, "--restore", line.restore, "continue from a checkpoint written by a run of the same scene")
      ->type_name("FILE");
  app.add_flag("--overwrite", line.overwrite, "write into an output directory that already holds a run's outputs");
  app.add_flag("-q,--quiet", line.quiet, "only warnings and errors");
  cli::addText(app, "--backend", line.backend,
               "engine: native (default) or liggghts (LIGGGHTS-PUBLIC on the MPI ranks mpirun started)")
      ->type_name("NAME");
  app.add_flag("--check", line.check,
               "validate the scene (translate it, check the time step and output intervals) without running; "
               "exit 0 if valid, 2 naming the field if not");
  CLI::Option* viewOption =
      cli::addText(app, "--view", line.view,
                   "serve a live 3D view of the run in a browser at ADDR:PORT (or PORT on 127.0.0.1; docs/view.md)")
          ->type_name("ADDR:PORT");
  demlink::server::addViewCapOptions(app, line.view_caps, viewOption);
  cli::addNumber(app, "--view-linger", line.view_linger, {0.0, false, 86400.0},
                 "keep the view serving the final state this long after the run ends [s]")
      ->type_name("S");
  cli::addNumber(app, "--pace", line.pace, {0.0, false, 1.0e6},
                 "with --view: run at most this many simulated seconds per wall second, to watch a fast scene")
      ->type_name("X");
  cli::addText(app, "--token", line.token, "access token the view's WebSocket requires (default: env DEMLINK_TOKEN)")
      ->type_name("T");
  if (const std::optional<int> exitCode = cli::parse(app, argc, argv)) return *exitCode;

  spdlog::set_pattern("[%H:%M:%S] %^%l%$: %v");
  if (line.quiet) spdlog::set_level(spdlog::level::warn);
  const demlink::server::BackendKind backend = demlink::server::parseBackendKind("--backend", line.backend);
  if (backend == demlink::server::BackendKind::Liggghts && line.view) {
    throw demlink::core::InputError("--view", *line.view,
                                    "a headless LIGGGHTS run has no live view; run the scene on the native backend, "
                                    "or serve it with demlink-server --backend liggghts --view");
  }
#ifdef DEMLINK_HAS_LIGGGHTS
  // Every rank runs the same calls; rank 0 alone reports progress.
  if (backend == demlink::server::BackendKind::Liggghts && demlink::server::ensureMpi() != 0) {
    spdlog::set_level(spdlog::level::warn);
  }
#else
  if (backend == demlink::server::BackendKind::Liggghts) {
    throw demlink::core::InputError("--backend", line.backend,
                                    "this build has no LIGGGHTS backend (configure with libliggghts-dev and "
                                    "libopenmpi-dev installed, DEMLINK_WITH_LIGGGHTS=ON)");
  }
#endif

  demlink::v1::Scene scene = demlink::server::loadSceneFile(line.scene);
  demlink::server::requireBackendAgrees(scene, backend);
  if (line.end_time) {
    for (demlink::v1::ComponentDeclaration& component : *scene.mutable_components()) {
      if (component.has_simulation_box()) component.mutable_simulation_box()->set_end_time(*line.end_time);
    }
  }
  const std::filesystem::path scenePath(line.scene);
  // Files the scene names must lie in its folder or below (an empty parent: the working directory).
  const std::filesystem::path sceneFolder = scenePath.has_parent_path() ? scenePath.parent_path() : ".";
  demlink::server::TranslatedScene translated = demlink::server::translateScene(scene, sceneFolder);
  if (line.output) {
    translated.run.output_directory = *line.output;
  } else if (translated.run.output_directory.empty()) {
    translated.run.output_directory = (std::filesystem::path("out") / scenePath.stem()).string();
  }
  translated.run.scene_file = line.scene;
  if (line.restore) translated.run.restore_file = *line.restore;
  translated.run.overwrite = line.overwrite;
  if (line.check) {
    demlink::server::checkHeadless(translated);
    if (backend == demlink::server::BackendKind::Liggghts) {
      demlink::server::requireLiggghtsCompatible(scene, translated.world);
    }
    std::printf("%s: valid (%zu particles at the start, time step %g s)\n", line.scene.c_str(),
                translated.world.particles().size(), translated.world.settings().time_step);
    return 0;
  }
  spdlog::info("scene {}", line.scene);
#ifdef DEMLINK_HAS_LIGGGHTS
  if (backend == demlink::server::BackendKind::Liggghts) {
    demlink::server::runHeadlessLiggghts(scene, translated);
    return 0;
  }
#endif
  if (!line.view) {
    demlink::server::runHeadless(translated);
    return 0;
  }
  demlink::server::ViewServerOptions viewOptions = line.view_caps;
  demlink::server::parseViewAddress(*line.view, "--view", viewOptions);
  if (!line.token) {
    if (const char* fromEnvironment = std::getenv("DEMLINK_TOKEN")) line.token = fromEnvironment;
  }
  viewOptions.access_token = line.token.value_or("");
  demlink::server::LiveViewHub hub;
  demlink::server::ViewServer view(hub, viewOptions);
  view.start();
  spdlog::info("view: {}{}", view.url(), viewOptions.access_token.empty() ? "" : "?token=<the access token>");
  const auto wallStart = std::chrono::steady_clock::now();
  std::optional<double> simulatedStart;
  const double pace = line.pace;
  demlink::server::runHeadless(translated, [&](const demlink::core::World& world) {
    hub.offer(world);
    if (pace <= 0.0) return;
    if (!simulatedStart) simulatedStart = world.time();
    // Sleep off whatever the run is ahead of the pace by more than a millisecond of wall time.
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    const double ahead = (world.time() - *simulatedStart) / pace - wall;
    if (ahead > 1.0e-3) std::this_thread::sleep_for(std::chrono::duration<double>(ahead));
  });
  hub.offerNow(translated.world);
  if (line.view_linger > 0.0) {
    spdlog::info("view: serving the final state for {} s", line.view_linger);
    std::this_thread::sleep_for(std::chrono::duration<double>(line.view_linger));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return demlink::server::runCommandLine(run, argc, argv); }
