/// Output folder policy (contract in output_directory.hpp).
#include "demlink/server/run/output_directory.hpp"

#include <spdlog/fmt/fmt.h>

#include <stdexcept>
#include <system_error>

#include "demlink/core/base/input_error.hpp"

namespace demlink::server {
namespace {

/// "<what>" or "<what>: <error message>".
std::string withCause(std::string what, const std::error_code& error) {
  if (error) what.append(": ").append(error.message());
  return what;
}

}  // namespace

void claimOutputDirectory(const std::filesystem::path& directory, bool overwrite, const std::string& field) {
  const std::string quoted = fmt::format("\"{}\"", directory.string());
  std::error_code error;
  if (!overwrite && std::filesystem::exists(directory, error) &&
      !(std::filesystem::is_directory(directory, error) && std::filesystem::is_empty(directory, error))) {
    throw core::InputError(field, quoted,
                           "the output folder is not empty; choose another folder or use --overwrite to write "
                           "into it (an earlier run's results there would be overwritten)");
  }
  std::filesystem::create_directories(directory, error);
  if (error || !std::filesystem::is_directory(directory)) {
    throw core::InputError(field, quoted, withCause("cannot create the output folder", error));
  }
}

std::filesystem::path simulationDirectory(const std::filesystem::path& root, std::uint64_t number) {
  return root / fmt::format("sim_{:03}", number);
}

std::uint64_t claimSimulationDirectory(const std::filesystem::path& root, std::uint64_t first) {
  std::error_code error;
  std::filesystem::create_directories(root, error);
  if (error || !std::filesystem::is_directory(root)) {
    throw std::runtime_error(withCause("cannot create the output root " + root.string(), error));
  }
  // create_directory is atomic: false means another run (or an earlier server) has it.
  for (std::uint64_t number = first;; ++number) {
    const std::filesystem::path directory = simulationDirectory(root, number);
    if (std::filesystem::create_directory(directory, error)) return number;
    if (error && !std::filesystem::exists(directory)) {
      throw std::runtime_error(withCause("cannot create " + directory.string(), error));
    }
  }
}

}  // namespace demlink::server
