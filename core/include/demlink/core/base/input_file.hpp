#pragma once
/// The one gate for every file a tool reads (scene, mesh, matrix, STL, particle files,
/// checkpoints, session records): it must be a regular file of bounded size. A FIFO would
/// block the reader forever and a device (/dev/zero) would be read until memory runs out,
/// so both are refused before the file is opened; a huge file is refused by its size
/// before any of it is read. Each refusal is an InputError naming the field and the path
/// (the tools exit 2 with it).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace demlink::core {

/// Largest file a tool reads [bytes]: 4 GiB, above any scene, mesh or checkpoint of a
/// world that fits the particle memory budget of a large machine.
inline constexpr std::uintmax_t kMaxInputFileBytes = std::uintmax_t{4} << 30;

/// Throws InputError(field, path, reason) unless `path` (symlinks followed) is a regular
/// file of at most `maxBytes`; returns its size [bytes].
std::uintmax_t requireInputFile(const std::string& field, const std::filesystem::path& path,
                                std::uintmax_t maxBytes = kMaxInputFileBytes);

/// requireInputFile, then the file opened for reading (binary when `binary`). Throws
/// InputError when it cannot be opened.
[[nodiscard]] std::ifstream openInputFile(const std::string& field, const std::filesystem::path& path,
                                          bool binary = false, std::uintmax_t maxBytes = kMaxInputFileBytes);

/// requireInputFile, then the whole file. Throws InputError when it cannot be read.
[[nodiscard]] std::string readInputFile(const std::string& field, const std::filesystem::path& path,
                                        std::uintmax_t maxBytes = kMaxInputFileBytes);

}  // namespace demlink::core
