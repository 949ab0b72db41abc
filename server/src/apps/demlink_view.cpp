/// demlink-view: the view of a finished run in a browser.
///
///   demlink-view OUTPUT_DIR [--view ADDR:PORT] [--token T]
///                [--view-max-connections N] [--view-max-rate R] [--view-max-bytes-per-second B]
///
/// Serves the live view's page over the run's particles.pvd series (and its meshes, planes
/// and deformable surfaces) with a timeline: slider, play and step (docs/view.md). Runs
/// until interrupted (SIGINT, SIGTERM). Exit codes as demlink-run: 2 bad input, 1 other.
#include <spdlog/spdlog.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "command_line_main.hpp"
#include "view_caps_command_line.hpp"
#include "demlink/cli/command_line.hpp"
#include "demlink/server/view/recorded_run.hpp"
#include "demlink/server/view/view_server.hpp"

namespace {

namespace cli = demlink::cli;

int run(int argc, char** argv) {
  std::string directory;
  std::string address = "127.0.0.1:8080";
  std::optional<std::string> token;
  demlink::server::ViewServerOptions options;
  CLI::App app("Serves a 3D view of a finished run's output folder in a browser.", "demlink-view");
  app.add_option("directory", directory, "a run's output folder (with particles.pvd)")->required()->type_name("OUTPUT_DIR");
  cli::addText(app, "--view", address, "address to serve the page at: ADDR:PORT or PORT (default 127.0.0.1:8080)")
      ->type_name("ADDR:PORT");
  cli::addText(app, "--token", token, "access token the page's WebSocket requires (default: env DEMLINK_TOKEN)")
      ->type_name("T");
  demlink::server::addViewCapOptions(app, options);
  if (const std::optional<int> exitCode = cli::parse(app, argc, argv)) return *exitCode;
  spdlog::set_pattern("[%H:%M:%S] %^%l%$: %v");
  if (!token) {
    if (const char* fromEnvironment = std::getenv("DEMLINK_TOKEN")) token = fromEnvironment;
  }

  demlink::server::RecordedRun recorded(directory, "OUTPUT_DIR");
  demlink::server::parseViewAddress(address, "--view", options);
  options.access_token = token.value_or("");
  // The server's thread inherits the blocked signals, so only sigwait below sees them.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  demlink::server::ViewServer server(recorded, options);
  server.start();
  std::printf("demlink-view: %u frames of %s at %s%s\n", recorded.frameCount(), directory.c_str(), server.url().c_str(),
              options.access_token.empty() ? "" : "?token=<the access token>");
  std::fflush(stdout);
  int received = 0;
  sigwait(&signals, &received);
  server.stop();
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return demlink::server::runCommandLine(run, argc, argv); }
