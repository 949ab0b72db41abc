#include "zip_writer.hpp"

#include <array>
#include <stdexcept>

namespace demlink::fmu {
namespace {

void put16(std::string& out, std::uint32_t v) {
  out.push_back(static_cast<char>(v & 0xffu));
  out.push_back(static_cast<char>((v >> 8) & 0xffu));
}
void put32(std::string& out, std::uint32_t v) {
  put16(out, v & 0xffffu);
  put16(out, v >> 16);
}
std::uint32_t get16(const std::string& in, std::size_t at) {
  if (at + 2 > in.size()) throw std::invalid_argument("zip: truncated archive");
  return static_cast<std::uint32_t>(static_cast<unsigned char>(in[at])) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(in[at + 1])) << 8;
}
std::uint32_t get32(const std::string& in, std::size_t at) { return get16(in, at) | get16(in, at + 2) << 16; }

constexpr std::uint32_t kLocalSignature = 0x04034b50u;
constexpr std::uint32_t kCentralSignature = 0x02014b50u;
constexpr std::uint32_t kEndSignature = 0x06054b50u;
constexpr std::uint32_t kDosDate1980 = (0u << 9) | (1u << 5) | 1u;  // 1980-01-01: reproducible archives

}  // namespace

std::uint32_t crc32(const std::string& data) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) != 0 ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xffffffffu;
  for (char ch : data) c = table[(c ^ static_cast<unsigned char>(ch)) & 0xffu] ^ (c >> 8);
  return c ^ 0xffffffffu;
}

std::string zipArchive(const std::vector<ZipEntry>& entries) {
  std::string out;
  std::string central;
  for (const ZipEntry& e : entries) {
    const std::uint32_t offset = static_cast<std::uint32_t>(out.size());
    const std::uint32_t crc = crc32(e.data);
    const auto size = static_cast<std::uint32_t>(e.data.size());
    const auto nameLength = static_cast<std::uint32_t>(e.name.size());
    put32(out, kLocalSignature);
    put16(out, 20);  // version needed: 2.0
    put16(out, 0);   // flags
    put16(out, 0);   // method: stored
    put16(out, 0);   // time
    put16(out, kDosDate1980);
    put32(out, crc);
    put32(out, size);
    put32(out, size);
    put16(out, nameLength);
    put16(out, 0);
    out += e.name;
    out += e.data;

    put32(central, kCentralSignature);
    put16(central, 0x031e);  // made by: Unix, 3.0
    put16(central, 20);
    put16(central, 0);
    put16(central, 0);
    put16(central, 0);
    put16(central, kDosDate1980);
    put32(central, crc);
    put32(central, size);
    put32(central, size);
    put16(central, nameLength);
    put16(central, 0);  // extra
    put16(central, 0);  // comment
    put16(central, 0);  // disk
    put16(central, 0);  // internal attributes
    put32(central, (e.name.ends_with(".so") ? 0100755u : 0100644u) << 16);  // Unix mode
    put32(central, offset);
    central += e.name;
  }
  const auto centralOffset = static_cast<std::uint32_t>(out.size());
  out += central;
  put32(out, kEndSignature);
  put16(out, 0);
  put16(out, 0);
  put16(out, static_cast<std::uint32_t>(entries.size()));
  put16(out, static_cast<std::uint32_t>(entries.size()));
  put32(out, static_cast<std::uint32_t>(central.size()));
  put32(out, centralOffset);
  put16(out, 0);
  return out;
}

std::vector<ZipEntry> readStoredZip(const std::string& archive) {
  std::vector<ZipEntry> out;
  std::size_t at = 0;
  while (at + 4 <= archive.size() && get32(archive, at) == kLocalSignature) {
    if (get16(archive, at + 8) != 0) throw std::invalid_argument("zip: entry is not stored");
    const std::uint32_t crc = get32(archive, at + 14);
    const std::uint32_t size = get32(archive, at + 18);
    const std::uint32_t nameLength = get16(archive, at + 26);
    const std::uint32_t extraLength = get16(archive, at + 28);
    const std::size_t dataAt = at + 30 + nameLength + extraLength;
    if (dataAt + size > archive.size()) throw std::invalid_argument("zip: truncated entry");
    ZipEntry e{archive.substr(at + 30, nameLength), archive.substr(dataAt, size)};
    if (crc32(e.data) != crc) throw std::invalid_argument("zip: CRC mismatch in " + e.name);
    out.push_back(std::move(e));
    at = dataAt + size;
  }
  if (out.empty()) throw std::invalid_argument("zip: no entries");
  return out;
}

}  // namespace demlink::fmu
