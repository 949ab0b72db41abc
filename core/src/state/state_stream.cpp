#include "demlink/core/state/state_stream.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

constexpr std::size_t kTagBytes = 4;
constexpr std::size_t kSectionHeaderBytes = kTagBytes + sizeof(std::uint64_t);

/// A tag as printable text for error messages (non-printable bytes as '?').
std::string printableTag(std::string_view tag) {
  std::string text(tag);
  for (char& c : text) {
    if (c < 32 || c > 126) c = '?';
  }
  return "\"" + text + "\"";
}

}  // namespace

void StateWriter::writeBytes(const void* data, std::size_t size) {
  buffer_.append(static_cast<const char*>(data), size);
}

void StateWriter::writeString(std::string_view text) {
  write<std::uint64_t>(text.size());
  writeBytes(text.data(), text.size());
}

std::size_t StateWriter::beginSection(std::string_view tag) {
  std::string padded(tag.substr(0, kTagBytes));
  padded.resize(kTagBytes, ' ');
  writeBytes(padded.data(), kTagBytes);
  const std::size_t handle = buffer_.size();
  write<std::uint64_t>(0);
  open_.push_back(handle);
  return handle;
}

void StateWriter::endSection(std::size_t handle) {
  const std::uint64_t length = buffer_.size() - handle - sizeof(std::uint64_t);
  std::memcpy(buffer_.data() + handle, &length, sizeof length);
  if (!open_.empty() && open_.back() == handle) open_.pop_back();
}

void writeWithMissing(StateWriter& out, const std::vector<double>& values) {
  std::vector<double> numbers(values);
  std::vector<std::uint8_t> missing(values.size(), 0);
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    if (std::isnan(numbers[i])) {
      numbers[i] = 0.0;
      missing[i] = 1;
    }
  }
  out.writeVector(numbers);
  out.writeVector(missing);
}

std::vector<double> readWithMissing(StateReader& in, const std::string& what) {
  std::vector<double> values = in.readVector<double>();
  const std::vector<std::uint8_t> missing = in.readVector<std::uint8_t>();
  requireSameLength(in, values, missing, what + ": values and missing flags");
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (missing[i] > 1) in.fail(std::to_string(missing[i]), what + ": a missing flag must be 0 or 1");
    if (missing[i] == 1) values[i] = std::numeric_limits<double>::quiet_NaN();
    if (std::isnan(values[i]) && missing[i] == 0) in.fail("NaN", what + ": a value that is not missing is NaN");
  }
  return values;
}

void StateWriter::refuseNaN() const {
  std::string path;
  for (const std::size_t handle : open_) {
    if (!path.empty()) path += '/';
    path += buffer_.substr(handle - kTagBytes, kTagBytes);
  }
  throw std::logic_error("checkpoint: a NaN value in section " + (path.empty() ? std::string("(none)") : path) +
                         " (a missing value must be written as a flag)");
}

StateReader::StateReader(std::string_view bytes, std::string source, std::string section)
    : bytes_(bytes), source_(std::move(source)), section_(std::move(section)) {}

void StateReader::fail(const std::string& value, const std::string& reason) const {
  throw InputError(source_ + ":" + section_, value, reason);
}

void StateReader::requireAvailable(std::uint64_t count, std::size_t elementBytes, const std::string& what) const {
  const std::uint64_t available = remaining() / (elementBytes > 0 ? elementBytes : 1);
  if (count > available) {
    fail(std::to_string(count), what + " exceeds the " + std::to_string(remaining()) +
                                    " bytes left in the section (truncated or corrupt file)");
  }
}

void StateReader::readBytes(void* out, std::size_t size) {
  if (size > remaining()) {
    fail("(" + std::to_string(remaining()) + " bytes left)",
         "unexpected end of data, " + std::to_string(size) + " bytes needed (truncated or corrupt file)");
  }
  std::memcpy(out, bytes_.data() + position_, size);
  position_ += size;
}

std::string StateReader::readString() {
  const auto length = read<std::uint64_t>();
  requireAvailable(length, 1, "string length");
  std::string text(bytes_.substr(position_, static_cast<std::size_t>(length)));
  position_ += static_cast<std::size_t>(length);
  return text;
}

std::string StateReader::peekTag() const {
  if (remaining() < kTagBytes) return {};
  return std::string(bytes_.substr(position_, kTagBytes));
}

StateReader StateReader::section(std::string_view tag, const std::string& name) {
  if (remaining() < kSectionHeaderBytes) {
    fail("(" + std::to_string(remaining()) + " bytes left)",
         "section " + printableTag(tag) + " (" + name + ") missing: the file ends early (truncated file)");
  }
  const std::string found = peekTag();
  if (found != tag) {
    fail(printableTag(found), "expected section " + printableTag(tag) + " (" + name + ") (corrupt file)");
  }
  position_ += kTagBytes;
  const auto length = read<std::uint64_t>();
  if (length > remaining()) {
    fail(std::to_string(length), "length of section " + printableTag(tag) + " (" + name + ") exceeds the " +
                                     std::to_string(remaining()) + " bytes left (truncated or corrupt file)");
  }
  StateReader inner(bytes_.substr(position_, static_cast<std::size_t>(length)), source_, name);
  position_ += static_cast<std::size_t>(length);
  return inner;
}

void StateReader::skipSection() {
  const std::string tag = peekTag();
  (void)section(tag, "skipped section " + printableTag(tag));
}

void StateReader::requireEnd() const {
  if (!atEnd()) fail(std::to_string(remaining()) + " bytes", "unexpected data at the end of the section (corrupt file)");
}

void readMatchingCount(StateReader& in, const std::string& what, std::size_t inScene) {
  const auto count = in.read<std::uint64_t>();
  requireEqual(in, what + " count " + std::to_string(count), count, static_cast<std::uint64_t>(inScene));
}

void requireIndices(const StateReader& in, const std::vector<std::uint32_t>& indices, std::size_t limit,
                    const std::string& what, bool removedAllowed) {
  constexpr std::uint32_t kRemoved = std::numeric_limits<std::uint32_t>::max();
  for (std::uint32_t index : indices) {
    if (index >= limit && !(removedAllowed && index == kRemoved)) {
      in.fail(std::to_string(index), what + " out of range (limit " + std::to_string(limit) + ")");
    }
  }
}

void requireOffsets(const StateReader& in, const std::vector<std::uint32_t>& offsets, std::size_t entries,
                    const std::string& what) {
  if (offsets.empty() || offsets.front() != 0 || offsets.back() != entries) {
    in.fail(what, "row offsets inconsistent with " + std::to_string(entries) + " entries");
  }
  for (std::size_t k = 1; k < offsets.size(); ++k) {
    if (offsets[k] < offsets[k - 1]) in.fail(what, "row offsets decrease");
  }
}

}  // namespace demlink::core
