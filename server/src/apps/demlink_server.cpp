/// demlink-server: the co-simulation server.
///
///   demlink-server [--listen ADDR] [--port N] [--token T] [--scene FILE] [--output DIR]
///                  [--quiet-period S] [--timeout S] [--max-frame-bytes N] [--record FILE]
///                  [--replay FILE] [--once] [--help]
///
/// Prints "demlink-server listening on ADDR:PORT" once it accepts connections (scripts and
/// tests read the port from it with --port 0). Exit codes: 0 normal end (also SIGINT /
/// SIGTERM: clients are told, outputs flushed); 2 bad input (command line, scene file, an
/// address that cannot be bound), printed as "error: <option> = <value>: <reason>";
/// 1 any other failure. Only 127.0.0.1 unless --listen says otherwise (security).
#include <spdlog/spdlog.h>

#include "demlink/server/net/asio.hpp"
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "demlink/core/input_error.hpp"
#include "demlink/server/cosim/co_simulation_host.hpp"
#include "demlink/server/cosim/session_replay.hpp"
#include "command_line_main.hpp"
#include "demlink/server/net/tcp_server.hpp"
#include "demlink/server/scene/scene_loader.hpp"


namespace {

using demlink::core::InputError;

constexpr const char* kUsage =
    "usage: demlink-server [options]\n"
    "  --listen ADDR          address to listen on (default 127.0.0.1; others only when given)\n"
    "  --port N               TCP port, 0 = any free port (default 47000)\n"
    "  --token T              access token clients must send in Hello (default: env DEMLINK_TOKEN)\n"
    "  --scene FILE           scene file whose components join every simulation\n"
    "  --output DIR           output root; simulation N writes DIR/sim_NNN (default out/cosim)\n"
    "  --quiet-period S       compile S seconds after the last Declare when nothing is expected (default 2)\n"
    "  --timeout S            a due client may take S seconds to send its package (default 30)\n"
    "  --max-frame-bytes N    largest accepted message [bytes] (default 67108864)\n"
    "  --record FILE          record every received message to FILE\n"
    "  --replay FILE          re-run a recorded session from FILE (no network) and exit\n"
    "  --once                 exit after the first simulation ends\n"
    "  --help                 this text\n";

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
  bool once = false;
  bool help = false;
};

template <typename Integer>
Integer parseInteger(std::string_view option, std::string_view text, Integer low, Integer high) {
  Integer value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < low || value > high) {
    throw InputError(std::string(option), std::string(text),
                     "must be an integer in " + std::to_string(low) + ".." + std::to_string(high));
  }
  return value;
}

/// Seconds; `positive`: > 0, else >= 0.
double parseSeconds(std::string_view option, std::string_view text, bool positive) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  const bool inRange = positive ? value > 0.0 : value >= 0.0;
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value) || !inRange) {
    throw InputError(std::string(option), std::string(text),
                     positive ? "must be a positive number of seconds" : "must be a number of seconds >= 0");
  }
  return value;
}

std::string nonEmpty(std::string_view option, std::string_view text) {
  if (text.empty()) throw InputError(std::string(option), "\"\"", "must not be empty");
  return std::string(text);
}

CommandLine parseCommandLine(int argc, char** argv) {
  CommandLine line;
  for (int k = 1; k < argc; ++k) {
    const std::string_view arg = argv[k];
    auto is = [&](std::string_view option) {
      return arg == option || (arg.starts_with(option) && arg.size() > option.size() && arg[option.size()] == '=');
    };
    auto valueOf = [&](std::string_view option) -> std::string_view {
      if (arg.size() > option.size()) return arg.substr(option.size() + 1);
      if (k + 1 >= argc) throw InputError(std::string(option), "(missing)", "expects a value");
      return argv[++k];
    };
    if (arg == "-h" || arg == "--help") {
      line.help = true;
    } else if (arg == "--once") {
      line.once = true;
    } else if (is("--listen")) {
      line.listen = nonEmpty("--listen", valueOf("--listen"));
      asio::error_code error;
      static_cast<void>(asio::ip::make_address(line.listen, error));
      if (error) throw InputError("--listen", line.listen, "not an IPv4 or IPv6 address");
    } else if (is("--port")) {
      line.port = parseInteger<std::uint16_t>("--port", valueOf("--port"), 0, 65535);
    } else if (is("--token")) {
      line.token = nonEmpty("--token", valueOf("--token"));
    } else if (is("--scene")) {
      line.scene = nonEmpty("--scene", valueOf("--scene"));
    } else if (is("--output")) {
      line.output = nonEmpty("--output", valueOf("--output"));
    } else if (is("--quiet-period")) {
      line.quiet_period = parseSeconds("--quiet-period", valueOf("--quiet-period"), false);
    } else if (is("--timeout")) {
      line.timeout = parseSeconds("--timeout", valueOf("--timeout"), true);
    } else if (is("--max-frame-bytes")) {
      // parsePayload takes at most INT_MAX bytes (protobuf's limit).
      line.max_frame_bytes = parseInteger<std::size_t>("--max-frame-bytes", valueOf("--max-frame-bytes"), 1,
                                                       std::numeric_limits<int>::max());
    } else if (is("--record")) {
      line.record = nonEmpty("--record", valueOf("--record"));
    } else if (is("--replay")) {
      line.replay = nonEmpty("--replay", valueOf("--replay"));
    } else {
      throw InputError("command line", std::string(arg), "unknown option\n" + std::string(kUsage));
    }
  }
  if (line.record && line.replay) {
    throw InputError("--record", *line.record, "cannot be combined with --replay");
  }
  return line;
}

demlink::server::CoSimulationOptions hostOptions(const CommandLine& line) {
  demlink::server::CoSimulationOptions options;
  if (line.scene) {
    options.base_scene = demlink::server::loadSceneFile(*line.scene);
    const std::filesystem::path directory = std::filesystem::path(*line.scene).parent_path();
    options.scene_directory = directory.empty() ? std::filesystem::path(".") : directory;
  }
  options.output_root = line.output;
  options.quiet_period_s = line.quiet_period;
  options.client_timeout_s = line.timeout;
  if (line.record) options.record_file = *line.record;
  return options;
}

int run(int argc, char** argv) {
  CommandLine line = parseCommandLine(argc, argv);
  if (line.help) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  spdlog::set_pattern("[%H:%M:%S] %^%l%$: %v");
  if (!line.token) {
    if (const char* fromEnvironment = std::getenv("DEMLINK_TOKEN"); fromEnvironment != nullptr && *fromEnvironment) {
      line.token = fromEnvironment;
    }
  }
  const demlink::server::CoSimulationOptions options = hostOptions(line);

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

  demlink::server::CoSimulationHost host(options);
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
