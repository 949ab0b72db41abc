/// demlink-run: headless mode from the command line.
///
///   demlink-run <scene.json> [--output DIR] [--end-time T] [--restore FILE] [--quiet]
///
/// Exit codes: 0 success; 2 bad input (scene, files, command line), printed as
/// "error: <field> = <value>: <reason>"; 1 any other failure (e.g. a disk full).
/// Command-line overrides are applied to the declarations before compilation,
/// so they are validated exactly like values from the scene file.
#include <spdlog/spdlog.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "demlink/core/input_error.hpp"
#include "command_line_main.hpp"
#include "demlink/server/run/headless_runner.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"

namespace {

using demlink::core::InputError;

constexpr const char* kUsage =
    "usage: demlink-run <scene.json> [--output DIR] [--end-time T] [--restore FILE] [--quiet]\n"
    "  --output DIR    output directory (default: the scene's output.directory, else out/<scene name>)\n"
    "  --end-time T    simulated end time [s], overrides simulation_box.end_time\n"
    "  --restore FILE  continue from a checkpoint written by a run of the same scene\n"
    "  --quiet         only warnings and errors\n";

struct CommandLine {
  std::string scene;
  std::optional<std::string> output;
  std::optional<double> end_time;  ///< [s]
  std::optional<std::string> restore;
  bool quiet = false;
  bool help = false;
};

double parseEndTime(std::string_view text) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value) || !(value > 0.0)) {
    throw InputError("--end-time", std::string(text), "must be a positive number of seconds");
  }
  return value;
}

CommandLine parseCommandLine(int argc, char** argv) {
  CommandLine line;
  for (int k = 1; k < argc; ++k) {
    const std::string_view arg = argv[k];
    auto valueOf = [&](std::string_view option) -> std::string_view {
      if (arg.size() > option.size() && arg.substr(0, option.size()) == option && arg[option.size()] == '=') {
        return arg.substr(option.size() + 1);
      }
      if (k + 1 >= argc) throw InputError(std::string(option), "(missing)", "expects a value");
      return argv[++k];
    };
    if (arg == "-h" || arg == "--help") {
      line.help = true;
    } else if (arg == "-q" || arg == "--quiet") {
      line.quiet = true;
    } else if (arg == "--output" || arg.starts_with("--output=")) {
      line.output = std::string(valueOf("--output"));
      if (line.output->empty()) throw InputError("--output", "\"\"", "must not be empty");
    } else if (arg == "--end-time" || arg.starts_with("--end-time=")) {
      line.end_time = parseEndTime(valueOf("--end-time"));
    } else if (arg == "--restore" || arg.starts_with("--restore=")) {
      line.restore = std::string(valueOf("--restore"));
      if (line.restore->empty()) throw InputError("--restore", "\"\"", "must not be empty");
    } else if (arg.starts_with("-") && arg.size() > 1) {
      throw InputError("command line", std::string(arg), "unknown option\n" + std::string(kUsage));
    } else if (line.scene.empty()) {
      line.scene = std::string(arg);
    } else {
      throw InputError("command line", std::string(arg), "only one scene file may be given");
    }
  }
  if (line.scene.empty() && !line.help) {
    throw InputError("command line", "(none)", "missing the scene file\n" + std::string(kUsage));
  }
  return line;
}

int run(int argc, char** argv) {
  const CommandLine line = parseCommandLine(argc, argv);
  if (line.help) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  spdlog::set_pattern("[%H:%M:%S] %^%l%$: %v");
  if (line.quiet) spdlog::set_level(spdlog::level::warn);

  demlink::v1::Scene scene = demlink::server::loadSceneFile(line.scene);
  if (line.end_time) {
    for (demlink::v1::ComponentDeclaration& component : *scene.mutable_components()) {
      if (component.has_simulation_box()) component.mutable_simulation_box()->set_end_time(*line.end_time);
    }
  }
  const std::filesystem::path scenePath(line.scene);
  demlink::server::TranslatedScene translated = demlink::server::translateScene(scene, scenePath.parent_path());
  if (line.output) {
    translated.run.output_directory = *line.output;
  } else if (translated.run.output_directory.empty()) {
    translated.run.output_directory = (std::filesystem::path("out") / scenePath.stem()).string();
  }
  translated.run.scene_file = line.scene;
  if (line.restore) translated.run.restore_file = *line.restore;
  spdlog::info("scene {}", line.scene);
  demlink::server::runHeadless(translated);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return demlink::server::runCommandLine(run, argc, argv); }
