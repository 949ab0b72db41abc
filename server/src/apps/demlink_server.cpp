/// demlink-server: the co-simulation server.
///
///   demlink-server [--listen ADDR] [--port N] [--token T] [--scene FILE] [--output DIR]
///                  [--quiet-period S] [--timeout S] [--max-frame-bytes N] [--record FILE]
///                  [--replay FILE] [--data-root DIR] [--overwrite] [--once] [--help] [--version]
///
/// Prints "demlink-server listening on ADDR:PORT" once it accepts connections (scripts and
/// tests read the port from it with --port 0). Exit codes: 0 normal end (also SIGINT /
/// SIGTERM: clients are told, outputs flushed); 2 bad input (command line, scene file, an
/// address that cannot be bound), printed as "error: <option> = <value>: <reason>";
/// 1 any other failure. Only 127.0.0.1 unless --listen says otherwise (security).
#include <spdlog/spdlog.h>

#include "demlink/server/net/asio.hpp"
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>

#include "demlink/core/input_error.hpp"
#include "demlink/server/cosim/cosim_host.hpp"
#include "demlink/server/cosim/session_replay.hpp"
#include "command_line_main.hpp"
#include "demlink/cli/command_line.hpp"
#include "demlink/server/net/tcp_server.hpp"
#include "demlink/server/scene/scene_loader.hpp"

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
  std::size_t max_frame_bytes = demlink::wire::kDefaultMaxFrameBytes;
  std::optional<std::string> record;
  std::optional<std::string> replay;
  std::optional<std::string> data_root;
  bool overwrite = false;
  bool once = false;
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
  app.add_flag("--overwrite", line.overwrite, "a simulation may write into an output folder that holds a run's outputs");
  app.add_flag("--once", line.once, "exit after the first simulation ends");
}

demlink::server::CosimOptions hostOptions(const CommandLine& line) {
  demlink::server::CosimOptions options;
  if (line.scene) {
    options.base_scene = demlink::server::loadSceneFile(*line.scene);
    const std::filesystem::path directory = std::filesystem::path(*line.scene).parent_path();
    options.scene_directory = directory.empty() ? std::filesystem::path(".") : directory;
  }
  if (line.data_root) options.data_root = std::filesystem::path(*line.data_root);
  options.output_root = line.output;
  options.overwrite = line.overwrite;
  options.quiet_period_s = line.quiet_period;
  options.client_timeout_s = line.timeout;
  if (line.record) options.record_file = *line.record;
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
  spdlog::set_pattern("[%H:%M:%S] %^%l%$: %v");
  if (!line.token) {
    if (const char* fromEnvironment = std::getenv("DEMLINK_TOKEN"); fromEnvironment != nullptr && *fromEnvironment) {
      line.token = fromEnvironment;
    }
  }
  const demlink::server::CosimOptions options = hostOptions(line);

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

  demlink::server::CosimHost host(options);
  demlink::server::TcpServerOptions net;
  net.listen_address = line.listen;
  net.port = line.port;
  net.access_token = line.token.value_or("");
  net.max_frame_bytes = line.max_frame_bytes;
  net.stop_on_signals = true;
  if (line.once) net.stop_when = [&host] { return host.simulationsFinished() >= 1; };
  demlink::server::TcpServer server(host, net);

  const asio::ip::address bound = asio::ip::make_address(server.address());
  if (!bound.is_loopback() && net.access_token.empty()) {
    spdlog::warn("listening on {} without an access token: anyone who can reach it can connect", server.address());
  }
  std::printf("demlink-server listening on %s:%u\n", server.address().c_str(), static_cast<unsigned>(server.port()));
  std::fflush(stdout);
  server.run();
  spdlog::info("demlink-server stopped");
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return demlink::server::runCommandLine(run, argc, argv); }
