/// demlink-server: the co-simulation server.
///
///   demlink-server [--listen ADDR] [--port N] [--token T] [--scene FILE] [--output DIR]
///                  [--quiet-period S] [--timeout S] [--assembly-timeout S] [--hello-timeout S]
///                  [--max-frame-bytes N] [--max-queued-bytes N] [--max-unwelcomed N]
///                  [--progress S] [--spin-wait-us US] [--record FILE] [--replay FILE] [--data-root DIR] [--overwrite]
///                  [--restore FILE]
///                  [--once | --max-simulations N] [--backend native|liggghts]
///                  [--view ADDR:PORT [--view-max-connections N] [--view-max-rate R] [--view-max-bytes-per-second B]]
///                  [--help] [--version]
///   mpirun -np N demlink-server --backend liggghts ...   (docs/scale-out.md)
///
/// Prints "demlink-server listening on ADDR:PORT" once it accepts connections (scripts and
/// tests read the port from it with --port 0). Exit codes: 0 normal end (also SIGINT /
/// SIGTERM: clients are told, outputs flushed); 2 bad input (command line, scene file, an
/// address that cannot be bound), printed as "error: <option> = <value>: <reason>";
/// 1 any other failure. Only 127.0.0.1 unless --listen says otherwise (security).
#include <spdlog/spdlog.h>
#include <unistd.h>

#include "demlink/server/net/asio.hpp"
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/input_file.hpp"
#include "demlink/server/backend/simulation_backend.hpp"
#ifdef DEMLINK_HAS_LIGGGHTS
#include "demlink/server/cosim/cosim_lockstep.hpp"
#include "demlink/server/backend/liggghts_backend.hpp"
#endif
#include "demlink/server/cosim/cosim_host.hpp"
#include "demlink/server/cosim/session_replay.hpp"
#include "demlink/server/cosim/simulation_hub.hpp"
#include "command_line_main.hpp"
#include "view_caps_command_line.hpp"
#include "demlink/cli/command_line.hpp"
#include "demlink/server/net/tcp_server.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "demlink/server/view/live_view_hub.hpp"
#include "demlink/server/view/view_server.hpp"

namespace {

namespace cli = demlink::cli;
using demlink::core::InputError;

struct CommandLine {
  std::string listen = "127.0.0.1";
  std::uint16_t port = 47000;
  std::optional<std::string> token;
  std::optional<std::string> scene;
  std::string output = "out/cosim";
  double quiet_period = 2.0;  ///< [s]
  double timeout = 30.0;      ///< [s]
  double assembly_timeout = 60.0;  ///< [s]; 0: none
  double hello_timeout = 10.0;     ///< [s]; 0: none
  double progress = 10.0;          ///< [s]; 0: none
  /// Spin before blocking in the network loop and the DEM threads [us]; unset: the default.
  std::optional<double> spin_wait_us;
  std::size_t max_frame_bytes = demlink::wire::kDefaultMaxFrameBytes;
  std::size_t max_queued_bytes = demlink::server::TcpServerOptions{}.max_queued_bytes;
  std::size_t max_unwelcomed = demlink::server::TcpServerOptions{}.max_unwelcomed;
  std::uint64_t max_simulations = 0;  ///< 0: no limit
  std::size_t max_open = demlink::server::SimulationHubOptions{}.max_open;
  std::size_t max_stepping = std::max(1u, std::thread::hardware_concurrency());
  std::optional<std::string> record;
  std::optional<std::string> replay;
  std::optional<std::string> data_root;
  std::optional<std::string> restore;
  bool overwrite = false;
  bool once = false;
  std::string backend = "native";
  std::optional<std::string> view;
  demlink::server::ViewServerOptions view_caps;  ///< the --view-max-* options
};

/// Registers the options on `app`, writing into `line`.
void addOptions(CLI::App& app, CommandLine& line) {
  cli::addValue(app, "--listen", "address to listen on (default 127.0.0.1; others only when given)",
                [&line](const std::string& text) {
                  if (text.empty()) cli::refuse("--listen", "\"\"", "must not be empty");
                  asio::error_code error;
                  static_cast<void>(asio::ip::make_address(text, error));
                  if (error) cli::refuse("--listen", text, "not an IPv4 or IPv6 address");
                  line.listen = text;
                })
      ->type_name("ADDR");
  cli::addWholeNumber<std::uint16_t>(app, "--port", line.port, 0, 65535, "TCP port, 0 = any free port (default 47000)");
  cli::addText(app, "--token", line.token, "access token clients must send in Hello (default: env DEMLINK_TOKEN)")
      ->type_name("T");
  cli::addText(app, "--scene", line.scene, "scene file whose components join every simulation")
      ->type_name("FILE");
  cli::addText(app, "--output", line.output, "output root; simulation N writes DIR/sim_NNN (default out/cosim)")
      ->type_name("DIR");
  cli::addNumber(app, "--quiet-period", line.quiet_period, {0.0, false, demlink::server::kMaxWaitSeconds},
                 "compile S seconds after the last Declare when nothing is expected (default 2)")
      ->type_name("S");
  cli::addNumber(app, "--timeout", line.timeout, {0.0, true, demlink::server::kMaxWaitSeconds},
                 "a due client may take S seconds to send its package (default 30)")
      ->type_name("S");
  // parsePayload takes at most INT_MAX bytes (protobuf's limit).
  cli::addWholeNumber<std::size_t>(app, "--max-frame-bytes", line.max_frame_bytes, 1,
                                   std::numeric_limits<int>::max(), "largest accepted message [bytes] (default 67108864)");
  cli::addNumber(app, "--assembly-timeout", line.assembly_timeout, {0.0, false},
                 "a simulation not compiled S seconds after its first client joined ends with TIMEOUT; 0: never "
                 "(default 60)")
      ->type_name("S");
  cli::addNumber(app, "--spin-wait-us", line.spin_wait_us, {0.0, false, 1e4},
                 "poll up to US microseconds for the next package (and DEM threads for their next loop) before "
                 "blocking, while a free CPU allows it; 0: block at once (default 50, or env DEMLINK_SPIN_WAIT_US)")
      ->type_name("US");
  cli::addNumber(app, "--hello-timeout", line.hello_timeout, {0.0, false},
                 "a connection without Hello S seconds after connecting is closed; 0: never (default 10)")
      ->type_name("S");
  cli::addWholeNumber<std::size_t>(app, "--max-queued-bytes", line.max_queued_bytes, 1,
                                   std::numeric_limits<std::size_t>::max() / 2,
                                   "output queued for one client above which its input waits [bytes] (default 16777216)");
  cli::addWholeNumber<std::size_t>(app, "--max-unwelcomed", line.max_unwelcomed, 1, 1u << 20,
                                   "connections awaiting Hello at once; more get SERVER_BUSY (default 64)");
  cli::addNumber(app, "--progress", line.progress, {0.0, false},
                 "a running simulation prints a progress line every S seconds; 0: never (default 10)")
      ->type_name("S");
  cli::addText(app, "--record", line.record, "record every received message to FILE")
      ->type_name("FILE");
  cli::addText(app, "--replay", line.replay, "re-run a recorded session from FILE (no network) and exit")
      ->type_name("FILE");
  cli::addValue(app, "--data-root", "folder the files clients name must lie in (default: clients may name no file)",
                [&line](const std::string& text) {
                  std::error_code error;
                  if (!std::filesystem::is_directory(text, error)) cli::refuse("--data-root", text, "not a folder");
                  line.data_root = text;
                })
      ->type_name("DIR");
  cli::addText(app, "--backend", line.backend,
               "engine: native (default) or liggghts (LIGGGHTS-PUBLIC on the MPI ranks mpirun started; rank 0 "
               "serves, docs/scale-out.md)")
      ->type_name("NAME");
  cli::addValue(app, "--restore",
                "the first simulation continues from this checkpoint of a co-simulation with the same declarations "
                "(docs/cosim.md)",
                [&line](const std::string& text) {
                  try {
                    demlink::core::requireInputFile("--restore", text);
                  } catch (const InputError& error) {
                    cli::refuse("--restore", text, error.reason());
                  }
                  line.restore = text;
                })
      ->type_name("FILE");
  CLI::Option* view = cli::addText(app, "--view", line.view,
                                   "serve a live 3D view of the running simulation in a browser at ADDR:PORT (or PORT "
                                   "on 127.0.0.1; docs/view.md); its WebSocket takes the --token")
                          ->type_name("ADDR:PORT");
  demlink::server::addViewCapOptions(app, line.view_caps, view);
  app.add_flag("--overwrite", line.overwrite, "a simulation may write into an output folder that holds a run's outputs");
  CLI::Option* once = app.add_flag("--once", line.once, "exit after the first simulation ends (= --max-simulations 1)");
  cli::addWholeNumber<std::size_t>(app, "--max-open-simulations", line.max_open, 1, 4096,
                                   "simulations pending or running at once; a client that would open one more gets "
                                   "SERVER_BUSY (default 8; 1 with --record)");
  cli::addWholeNumber<std::size_t>(app, "--max-stepping", line.max_stepping, 1, 4096,
                                   "simulations stepping at once; the others wait for a turn (default: the "
                                   "machine's hardware threads)");
  cli::addWholeNumber<std::uint64_t>(app, "--max-simulations", line.max_simulations, 1,
                                     std::numeric_limits<std::uint64_t>::max(),
                                     "exit after N simulations ended (default: serve until stopped)")
      ->excludes(once);
}

/// Translates the scene file's components once at start-up, so a bad scene stops the server
/// (exit 2, naming the field) instead of failing every simulation's compile. A scene without
/// a simulation_box (a client declares it) is checked with a placeholder box; everything
/// else the file references must be in the file. A pit is checked, not settled (each
/// compile settles it).
void checkBaseScene(const demlink::v1::Scene& scene, const std::filesystem::path& directory) {
  demlink::v1::Scene whole = scene;
  const bool hasBox = std::any_of(scene.components().begin(), scene.components().end(),
                                  [](const demlink::v1::ComponentDeclaration& c) { return c.has_simulation_box(); });
  if (!hasBox) {
    demlink::v1::ComponentDeclaration& box = *whole.add_components();
    box.set_name("(start-up check)");
    box.mutable_simulation_box();
  }
  // Quiet: the first line printed stays "listening on" (scripts read the port from it), and
  // each compile translates the scene again and prints its warnings there.
  const spdlog::level::level_enum level = spdlog::get_level();
  spdlog::set_level(spdlog::level::err);
  try {
    static_cast<void>(demlink::server::translateScene(whole, directory, demlink::server::SceneUse::CosimCheck));
  } catch (...) {
    spdlog::set_level(level);
    throw;
  }
  spdlog::set_level(level);
}

demlink::server::CosimOptions hostOptions(const CommandLine& line) {
  demlink::server::CosimOptions options;
  if (line.scene) {
    options.base_scene = demlink::server::loadSceneFile(*line.scene);
    const std::filesystem::path directory = std::filesystem::path(*line.scene).parent_path();
    options.scene_directory = directory.empty() ? std::filesystem::path(".") : directory;
    checkBaseScene(options.base_scene, options.scene_directory);
  }
  options.assembly_timeout_s = line.assembly_timeout;
  options.progress_interval_s = line.progress;
  if (line.data_root) options.data_root = std::filesystem::path(*line.data_root);
  options.output_root = line.output;
  options.overwrite = line.overwrite;
  options.quiet_period_s = line.quiet_period;
  options.client_timeout_s = line.timeout;
  if (line.record) options.record_file = *line.record;
  if (line.restore) options.restore_file = *line.restore;
  return options;
}

int run(int argc, char** argv) {
  CommandLine line;
  CLI::App app("The co-simulation server: system-model clients declare components, the server runs the DEM.",
               "demlink-server");
  addOptions(app, line);
  if (const std::optional<int> exitCode = cli::parse(app, argc, argv)) return *exitCode;
  if (line.record && line.replay) {
    throw InputError("--record", *line.record, "cannot be combined with --replay");
  }
  const demlink::server::BackendKind backend = demlink::server::parseBackendKind("--backend", line.backend);
  spdlog::set_pattern("[%H:%M:%S] %^%l%$: %v");
  if (!line.token) {
    if (const char* fromEnvironment = std::getenv("DEMLINK_TOKEN"); fromEnvironment != nullptr && *fromEnvironment) {
      line.token = fromEnvironment;
    }
  }
  demlink::server::CosimOptions options = hostOptions(line);
  options.backend = backend;
  // Under MPI rank 0 is the server; the other ranks mirror its host (cosim_lockstep.hpp).
  std::function<void()> stopMirrors;  // outlives the host, which calls into the leader
  bool stepsOffTheNetworkThread = backend == demlink::server::BackendKind::Native;
  if (backend == demlink::server::BackendKind::Liggghts) {
#ifdef DEMLINK_HAS_LIGGGHTS
    if (line.replay) throw InputError("--replay", *line.replay, "replays run on the native backend");
    if (line.restore) {
      // LIGGGHTS continues from the restart file beside our checkpoint (liggghts_backend.hpp).
      for (const char* extension : {".liggghts", ".liggghts_ids"}) {
        const std::filesystem::path part = std::filesystem::path(*line.restore).replace_extension(extension);
        if (!std::filesystem::is_regular_file(part)) {
          throw InputError("--restore", *line.restore, "the LIGGGHTS checkpoint file " + part.string() + " is missing");
        }
      }
    }
    options.liggghts = [](demlink::core::World& world, const std::filesystem::path& logFile,
                          const std::filesystem::path& restore) {
      return std::make_unique<demlink::server::LiggghtsBackend>(world, logFile.string(), restore);
    };
    if (demlink::server::ensureMpi() != 0) {
      spdlog::set_level(spdlog::level::warn);  // rank 0 reports
      demlink::server::runLockstepMirror(options);
      return 0;
    }
    auto leader = std::make_shared<demlink::server::LockstepLeader>();
    leader->attach(options);
    stopMirrors = [leader] { leader->close(); };
    // Under mpirun a signal for the server goes to this process: mpirun forwards one late
    // and kills the ranks a second after (docs/scale-out.md).
    spdlog::info("LIGGGHTS backend on {} MPI rank(s); rank 0 (this server) is process {}", demlink::server::mpiRanks(),
                 static_cast<long>(::getpid()));
    stepsOffTheNetworkThread = demlink::server::mpiCallsFromAnyThread();
    if (!stepsOffTheNetworkThread) {
      spdlog::warn("this MPI library keeps MPI calls on the thread that started it: the simulation steps on the "
                   "network thread, which answers nobody while an interval runs");
    }
#else
    throw InputError("--backend", line.backend,
                     "this build has no LIGGGHTS backend (configure with libliggghts-dev and libopenmpi-dev; "
                     "docs/scale-out.md)");
#endif
  }

  if (line.replay) {
    const demlink::server::ReplayResult result = demlink::server::replaySession(*line.replay, options);
    // Errors are part of the recorded session (the live run saw them too), not a replay failure.
    for (const demlink::v1::Error& error : result.errors) {
      spdlog::warn("replayed error {}: {}", demlink::v1::Error::Code_Name(error.code()), error.message());
    }
    std::printf("replayed %llu events, %llu simulation(s); last output in %s\n",
                static_cast<unsigned long long>(result.events), static_cast<unsigned long long>(result.simulations),
                result.output_directory.string().c_str());
    return 0;
  }

  // The view runs on its own thread; the simulations offer it their worlds after each step.
  std::unique_ptr<demlink::server::LiveViewHub> viewHub;
  std::unique_ptr<demlink::server::ViewServer> view;
  if (line.view) {
    demlink::server::ViewServerOptions viewOptions = line.view_caps;
    demlink::server::parseViewAddress(*line.view, "--view", viewOptions);
    viewOptions.access_token = line.token.value_or("");
    viewHub = std::make_unique<demlink::server::LiveViewHub>();
    view = std::make_unique<demlink::server::ViewServer>(*viewHub, viewOptions);
    options.open_observer = [hub = viewHub.get()](const demlink::core::World& world, const std::string& name) {
      hub->announce(world, name);
    };
    options.step_observer = [hub = viewHub.get()](const demlink::core::World& world) { hub->offer(world); };
    options.close_observer = [hub = viewHub.get()](const demlink::core::World& world) { hub->release(world); };
    view->start();
  }
  // Every simulation steps on its own thread (SimulationHub), so the network loop answers
  // whatever a simulation does and a signal cuts an interval short. LIGGGHTS under MPI: one
  // simulation at a time (the mirrors follow one host's events); only an MPI library
  // without thread support keeps it on the network thread.
  const std::uint64_t maxSimulations = line.once ? 1 : line.max_simulations;
  std::optional<std::chrono::nanoseconds> spinBudget;
  if (line.spin_wait_us) {
    spinBudget = std::chrono::nanoseconds(static_cast<std::int64_t>(*line.spin_wait_us * 1e3));
    demlink::core::setDefaultSpinBudget(*spinBudget);  // the worlds' thread pools
  }
  std::unique_ptr<demlink::server::SessionHandler> handler;
  std::function<std::uint64_t()> finished;
  if (stepsOffTheNetworkThread) {
    const bool native = backend == demlink::server::BackendKind::Native;
    demlink::server::SimulationHubOptions hubOptions;
    hubOptions.spin_wait = demlink::core::defaultSpinBudget();  // the network loop's
    hubOptions.max_open = native ? line.max_open : 1;
    hubOptions.max_stepping = line.max_stepping;
    hubOptions.max_total = maxSimulations;
    auto hub = std::make_unique<demlink::server::SimulationHub>(options, hubOptions);
    finished = [hub = hub.get()] { return hub->simulationsFinished(); };
    handler = std::move(hub);
  } else {
    auto host = std::make_unique<demlink::server::CosimHost>(options);
    finished = [host = host.get()] { return host->simulationsFinished(); };
    handler = std::move(host);
  }
  demlink::server::TcpServerOptions net;
  net.listen_address = line.listen;
  net.port = line.port;
  net.access_token = line.token.value_or("");
  net.max_frame_bytes = line.max_frame_bytes;
  net.max_queued_bytes = line.max_queued_bytes;
  net.max_unwelcomed = line.max_unwelcomed;
  net.hello_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(line.hello_timeout * 1000.0));
  net.stop_on_signals = true;
  if (line.spin_wait_us) net.spin_wait = *spinBudget;
  if (maxSimulations > 0) {
    net.stop_when = [&finished, maxSimulations] { return finished() >= maxSimulations; };
  }
  demlink::server::TcpServer server(*handler, net);

  const asio::ip::address bound = asio::ip::make_address(server.address());
  if (!bound.is_loopback() && net.access_token.empty()) {
    spdlog::warn("listening on {} without an access token: anyone who can reach it can connect", server.address());
  }
  // The listening line first: tools that start the server read its port from the first line.
  std::printf("demlink-server listening on %s:%u\n", server.address().c_str(), static_cast<unsigned>(server.port()));
  if (view) {
    std::printf("demlink-server view at %s%s\n", view->url().c_str(),
                line.token.value_or("").empty() ? "" : "?token=<the access token>");
  }
  std::fflush(stdout);
  server.run();
  if (stopMirrors) stopMirrors();
  spdlog::info("demlink-server stopped");
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return demlink::server::runCommandLine(run, argc, argv); }
