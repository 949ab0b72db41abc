/// Binary view frames (layout in frame_encoder.hpp).
#include "demlink/server/view/frame_encoder.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace demlink::server {
namespace {

static_assert(std::endian::native == std::endian::little, "view frames are written in the machine's byte order");

std::size_t alignedTo4(std::size_t bytes) { return (bytes + 3) & ~std::size_t{3}; }

class FrameWriter {
 public:
  explicit FrameWriter(std::vector<std::uint8_t>& out) : out_(out) {}
  template <class T>
  void put(T value) {
    const std::size_t at = out_.size();
    out_.resize(at + sizeof(T));
    std::memcpy(out_.data() + at, &value, sizeof(T));
  }
  template <class T>
  void putAt(std::size_t at, T value) {
    std::memcpy(out_.data() + at, &value, sizeof(T));
  }
  void pad() { out_.resize(alignedTo4(out_.size()), 0); }
  /// Grows by `bytes` and returns where they start.
  std::uint8_t* reserve(std::size_t bytes) {
    const std::size_t at = out_.size();
    out_.resize(at + bytes);
    return out_.data() + at;
  }
  void putPose(const ViewPose& pose) {
    for (const float v : pose.position) put(v);
    for (const float v : pose.orientation) put(v);
  }

 private:
  std::vector<std::uint8_t>& out_;
};

double colourValue(const ViewSnapshot& snapshot, ColourField field, std::size_t slot) {
  switch (field) {
    case ColourField::kSpeed:
      return slot < snapshot.speed.size() ? snapshot.speed[slot] : 0.0;
    case ColourField::kForce:
      return slot < snapshot.force.size() ? snapshot.force[slot] : 0.0;
    case ColourField::kMaterial:
      return static_cast<double>(snapshot.material[slot]);
    case ColourField::kId:
      return static_cast<double>(snapshot.id[slot]);
  }
  return 0.0;
}

}  // namespace

std::uint32_t subsetRank(std::uint64_t id) {
  // The finaliser of splitmix64: consecutive ids land far apart, so any prefix of the
  // ranking is spread evenly over the particles.
  std::uint64_t z = id + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return static_cast<std::uint32_t>((z ^ (z >> 31)) >> 32);
}

void chooseSubset(std::span<const std::uint64_t> ids, std::size_t maxParticles, std::vector<std::uint32_t>& slots,
                  std::vector<std::uint64_t>& ranks) {
  slots.clear();
  if (ids.size() <= maxParticles) {
    slots.resize(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) slots[i] = static_cast<std::uint32_t>(i);
    return;
  }
  if (maxParticles == 0) return;
  // Rank and id in one key, so equal ranks order by id and the cut is the same whatever
  // the slot order.
  ranks.resize(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ranks[i] = (std::uint64_t{subsetRank(ids[i])} << 32) | (ids[i] & 0xFFFFFFFFull);
  std::nth_element(ranks.begin(), ranks.begin() + static_cast<std::ptrdiff_t>(maxParticles - 1), ranks.end());
  const std::uint64_t cut = ranks[maxParticles - 1];
  for (std::size_t i = 0; i < ids.size() && slots.size() < maxParticles; ++i) {
    const std::uint64_t key = (std::uint64_t{subsetRank(ids[i])} << 32) | (ids[i] & 0xFFFFFFFFull);
    if (key <= cut) slots.push_back(static_cast<std::uint32_t>(i));
  }
}

std::uint16_t quantise(double value, double lower, double upper) {
  if (!(upper > lower) || !std::isfinite(value)) return 0;
  const double scaled = (value - lower) / (upper - lower) * 65535.0;
  return static_cast<std::uint16_t>(std::lround(std::clamp(scaled, 0.0, 65535.0)));
}

void encodeFrame(const ViewSnapshot& snapshot, const FrameRequest& request, FrameScratch& scratch,
                 std::vector<std::uint8_t>& out) {
  chooseSubset(snapshot.id, request.max_particles, scratch.slots, scratch.ranks);
  const std::vector<std::uint32_t>& slots = scratch.slots;
  float largestRadius = 0.0f;
  double colourMin = std::numeric_limits<double>::infinity();
  double colourMax = -std::numeric_limits<double>::infinity();
  for (const std::uint32_t slot : slots) {
    largestRadius = std::max(largestRadius, snapshot.radius[slot]);
    const double value = colourValue(snapshot, request.colour, slot);
    colourMin = std::min(colourMin, value);
    colourMax = std::max(colourMax, value);
  }
  if (slots.empty()) colourMin = colourMax = 0.0;

  out.clear();
  FrameWriter writer(out);
  const ViewStatus& status = snapshot.status;
  writer.put(kFrameMagic);
  writer.put(kFrameVersion);
  writer.put(status.time);
  writer.put(static_cast<double>(status.step));
  writer.put(status.real_time_factor);
  writer.put(status.steps_per_second);
  writer.put(status.particle_mass);
  writer.put(status.inserted_mass);
  writer.put(status.removed_mass);
  writer.put(status.initial_mass);
  writer.put(static_cast<std::uint32_t>(snapshot.particleCount()));
  writer.put(static_cast<std::uint32_t>(slots.size()));
  for (const float v : snapshot.box_lower) writer.put(v);
  for (const float v : snapshot.box_upper) writer.put(v);
  writer.put(largestRadius);
  writer.put(static_cast<float>(colourMin));
  writer.put(static_cast<float>(colourMax));
  writer.put(static_cast<std::uint32_t>(request.colour));
  writer.put(static_cast<std::uint32_t>(snapshot.meshes.size()));
  writer.put(static_cast<std::uint32_t>(snapshot.surfaces.size()));
  writer.put(static_cast<std::uint32_t>(snapshot.regions.size()));
  writer.put(request.frame_index);
  writer.put(request.frame_count);
  writer.put(std::uint32_t{0});

  const std::size_t m = slots.size();
  std::uint8_t* positions = writer.reserve(6 * m);
  for (std::size_t k = 0; k < m; ++k) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const std::uint16_t q = quantise(snapshot.position[3 * slots[k] + axis], snapshot.box_lower[axis],
                                       snapshot.box_upper[axis]);
      std::memcpy(positions + 2 * (3 * k + axis), &q, 2);
    }
  }
  writer.pad();
  std::uint8_t* radii = writer.reserve(2 * m);
  for (std::size_t k = 0; k < m; ++k) {
    const std::uint16_t q = quantise(snapshot.radius[slots[k]], 0.0, largestRadius);
    std::memcpy(radii + 2 * k, &q, 2);
  }
  writer.pad();
  std::uint8_t* colours = writer.reserve(2 * m);
  for (std::size_t k = 0; k < m; ++k) {
    const std::uint16_t q = quantise(colourValue(snapshot, request.colour, slots[k]), colourMin, colourMax);
    std::memcpy(colours + 2 * k, &q, 2);
  }
  writer.pad();
  for (const ViewPose& pose : snapshot.meshes) writer.putPose(pose);
  for (const ViewRegion& region : snapshot.regions) {
    writer.put(region.kind);
    for (const float v : region.half_size) writer.put(v);
    writer.putPose(region.pose);
  }
  for (const ViewSurface& surface : snapshot.surfaces) {
    writer.put(static_cast<std::uint32_t>(surface.positions.size() / 3));
    writer.put(static_cast<std::uint32_t>(surface.triangle_active.size()));
    writer.put(static_cast<std::uint32_t>(surface.spring_intact.size()));
    for (const float v : surface.positions) writer.put(v);
    for (const std::vector<std::uint8_t>* flags : {&surface.triangle_active, &surface.spring_intact}) {
      if (!flags->empty()) std::memcpy(writer.reserve(flags->size()), flags->data(), flags->size());
      writer.pad();
    }
  }
}

}  // namespace demlink::server
