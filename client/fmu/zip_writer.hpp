#pragma once
/// A minimal ZIP archive writer (stored entries, no compression): what an FMU needs, without
/// a zip library or an external zip program. Format: PKWARE APPNOTE.TXT, local file headers,
/// central directory, end of central directory record (no ZIP64: entries < 4 GiB).
#include <cstdint>
#include <string>
#include <vector>

namespace demlink::fmu {

struct ZipEntry {
  std::string name;  ///< path inside the archive, '/' separated
  std::string data;
};

/// CRC-32 (IEEE 802.3, as ZIP uses).
std::uint32_t crc32(const std::string& data);
/// The archive's bytes.
std::string zipArchive(const std::vector<ZipEntry>& entries);
/// The entries of an archive written by zipArchive (stored entries only); throws
/// std::invalid_argument for anything else. Used by the tests' FMI master.
std::vector<ZipEntry> readStoredZip(const std::string& archive);

}  // namespace demlink::fmu
