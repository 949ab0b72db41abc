/// The gate for files a tool reads (contract in input_file.hpp).
#include "demlink/core/base/input_file.hpp"

#include <sstream>
#include <system_error>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"

namespace demlink::core {
namespace {

std::string shown(const std::filesystem::path& path) { return logText(path.string()); }

}  // namespace

std::uintmax_t requireInputFile(const std::string& field, const std::filesystem::path& path, std::uintmax_t maxBytes) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw InputError(field, shown(path), "no such file");
  if (!std::filesystem::is_regular_file(status)) {
    const char* what = std::filesystem::is_directory(status)  ? "a folder"
                       : std::filesystem::is_fifo(status)     ? "a FIFO"
                       : std::filesystem::is_character_file(status) || std::filesystem::is_block_file(status)
                           ? "a device"
                       : std::filesystem::is_socket(status) ? "a socket"
                                                            : "not a plain file";
    throw InputError(field, shown(path), std::string("is not a regular file (") + what + ")");
  }
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error) throw InputError(field, shown(path), "cannot read its size: " + error.message());
  if (size > maxBytes) {
    throw InputError(field, shown(path),
                     "is " + std::to_string(size) + " bytes; at most " + std::to_string(maxBytes) + " are read");
  }
  return size;
}

std::ifstream openInputFile(const std::string& field, const std::filesystem::path& path, bool binary,
                            std::uintmax_t maxBytes) {
  requireInputFile(field, path, maxBytes);
  std::ifstream in(path, binary ? std::ios::in | std::ios::binary : std::ios::in);
  if (!in) throw InputError(field, shown(path), "cannot be opened for reading");
  return in;
}

std::string readInputFile(const std::string& field, const std::filesystem::path& path, std::uintmax_t maxBytes) {
  std::ifstream in = openInputFile(field, path, true, maxBytes);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw InputError(field, shown(path), "cannot be read");
  return bytes.str();
}

}  // namespace demlink::core
