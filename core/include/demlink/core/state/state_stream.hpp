#pragma once
/// A small binary stream for checkpoints: tagged, length-prefixed sections of
/// native-endian scalars, strings and arrays.
///
/// Why our own format and not protobuf or HDF5: core/ must not depend on either,
/// a checkpoint must reproduce every bit of a double (text would need care), and
/// the reader must survive any file a user hands it. So the writer builds the
/// whole file in memory, and the reader works on the whole file in memory: every
/// length is checked against the bytes that remain before anything is allocated,
/// and every failure is an InputError naming the file and the section.
///
/// Layout of a section: 4-byte ASCII tag, u64 payload length, payload. Sections
/// nest (a component's state is a section inside the component section), and a
/// reader can skip a section it does not need, which keeps the format easy to
/// extend: a new kind of state is a new tag.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

class StateWriter;
class StateReader;

/// How one element type is stored: kBytes on disk, written and read field by
/// field. Specialised for the arithmetic types, Vec3 and Quat; checkpoint code
/// may specialise it for its own plain structs.
template <class T, class Enable = void>
struct StateCodec;

class StateWriter {
 public:
  /// Appends raw bytes.
  void writeBytes(const void* data, std::size_t size);

  template <class T>
  void write(const T& value) {
    StateCodec<T>::write(*this, value);
  }
  void writeString(std::string_view text);
  /// Writes the element count (u64) and every element.
  template <class T>
  void writeVector(const std::vector<T>& values) {
    write<std::uint64_t>(values.size());
    for (const T& value : values) write(value);
  }

  /// Starts a section with a 4-character tag; returns a handle for endSection.
  [[nodiscard]] std::size_t beginSection(std::string_view tag);
  /// Fills in the length of the section started at `handle`.
  void endSection(std::size_t handle);
  /// Writes a section tagged `tag` whose payload is whatever `writePayload()` writes.
  template <class WritePayload>
  void section(std::string_view tag, WritePayload&& writePayload) {
    const std::size_t handle = beginSection(tag);
    writePayload();
    endSection(handle);
  }

  [[nodiscard]] const std::string& bytes() const { return buffer_; }

  /// A checkpoint never holds NaN (a missing value is written as its own flag): throws
  /// std::logic_error naming the open sections. The codecs call it for each NaN.
  [[noreturn]] void refuseNaN() const;

 private:
  std::string buffer_;
  std::vector<std::size_t> open_;  ///< handles of the sections begun and not yet ended
};

class StateReader {
 public:
  /// Reads `bytes` (not copied: it must outlive the reader). `source` (a file name)
  /// and `section` name the place in errors.
  StateReader(std::string_view bytes, std::string source, std::string section);

  /// Copies `size` bytes; throws InputError if fewer remain.
  void readBytes(void* out, std::size_t size);

  template <class T>
  T read() {
    T value{};
    StateCodec<T>::read(*this, value);
    return value;
  }
  std::string readString();
  /// Reads a vector written by writeVector; the count is checked against the
  /// bytes that remain before allocating.
  template <class T>
  std::vector<T> readVector() {
    const auto count = read<std::uint64_t>();
    requireAvailable(count, StateCodec<T>::kBytes, "array length");
    std::vector<T> values(static_cast<std::size_t>(count));
    for (T& value : values) StateCodec<T>::read(*this, value);
    return values;
  }

  /// Reads the next section, which must have tag `tag`; `name` names it in errors.
  /// The returned reader covers the section's payload; this one moves past it.
  StateReader section(std::string_view tag, const std::string& name);
  /// Tag of the next section without consuming it (empty at the end).
  [[nodiscard]] std::string peekTag() const;
  /// Moves past the next section, whatever its tag.
  void skipSection();

  [[nodiscard]] bool atEnd() const { return position_ == bytes_.size(); }
  [[nodiscard]] std::size_t remaining() const { return bytes_.size() - position_; }
  /// Throws InputError unless the section was read to its end.
  void requireEnd() const;
  /// Throws InputError naming this file and section.
  [[noreturn]] void fail(const std::string& value, const std::string& reason) const;
  /// Throws unless count elements of elementBytes each fit in the remaining bytes.
  void requireAvailable(std::uint64_t count, std::size_t elementBytes, const std::string& what) const;

  [[nodiscard]] const std::string& source() const { return source_; }
  [[nodiscard]] const std::string& sectionName() const { return section_; }

 private:
  std::string_view bytes_;
  std::size_t position_ = 0;
  std::string source_;
  std::string section_;
};

/// Checks shared by the objects that restore themselves; each throws through
/// in.fail(), naming the file and the section being read.

/// `inFile` (read from the checkpoint) must equal `inScene` (the world it is restored into).
template <class T>
void requireEqual(const StateReader& in, const std::string& what, const T& inFile, const T& inScene) {
  if (!(inFile == inScene)) {
    in.fail(what, "the checkpoint differs from the scene (restore into a world built from the same scene)");
  }
}
/// Reads a u64 count that must equal `inScene` (error field "<what> count <n>").
void readMatchingCount(StateReader& in, const std::string& what, std::size_t inScene);
/// Every index is below `limit`, or the removed-slot marker (UINT32_MAX) when `removedAllowed`.
void requireIndices(const StateReader& in, const std::vector<std::uint32_t>& indices, std::size_t limit,
                    const std::string& what, bool removedAllowed = false);
/// Row offsets start at 0, never decrease and end at `entries`.
void requireOffsets(const StateReader& in, const std::vector<std::uint32_t>& offsets, std::size_t entries,
                    const std::string& what);
/// Two parallel arrays have the same length.
template <class A, class B>
void requireSameLength(const StateReader& in, const A& a, const B& b, const std::string& what) {
  if (a.size() != b.size()) in.fail(std::to_string(a.size()) + " vs " + std::to_string(b.size()), what);
}

/// Numbers in which NaN marks a missing value (a sampled row: an empty CSV cell): written
/// as the values with 0 in place of each missing one, then a flag byte per value (1:
/// missing), so the file holds no NaN; read back with the NaNs in place.
void writeWithMissing(StateWriter& out, const std::vector<double>& values);
[[nodiscard]] std::vector<double> readWithMissing(StateReader& in, const std::string& what);

template <class T>
struct StateCodec<T, std::enable_if_t<std::is_arithmetic_v<T>>> {
  static constexpr std::size_t kBytes = sizeof(T);
  static void write(StateWriter& out, const T& value) {
    if constexpr (std::is_floating_point_v<T>) {
      if (std::isnan(value)) out.refuseNaN();
    }
    out.writeBytes(&value, sizeof(T));
  }
  static void read(StateReader& in, T& value) { in.readBytes(&value, sizeof(T)); }
};

template <>
struct StateCodec<Vec3> {
  static constexpr std::size_t kBytes = 3 * sizeof(double);
  static void write(StateWriter& out, const Vec3& value) {
    if (value.hasNaN()) out.refuseNaN();
    out.writeBytes(value.data(), kBytes);
  }
  static void read(StateReader& in, Vec3& value) { in.readBytes(value.data(), kBytes); }
};

template <>
struct StateCodec<Quat> {
  static constexpr std::size_t kBytes = 4 * sizeof(double);
  static void write(StateWriter& out, const Quat& value) {
    if (value.coeffs().hasNaN()) out.refuseNaN();
    out.writeBytes(value.coeffs().data(), kBytes);
  }
  static void read(StateReader& in, Quat& value) { in.readBytes(value.coeffs().data(), kBytes); }
};

}  // namespace demlink::core
