// The view's binary frames: header fields, the quantisation error bound, the stable
// subset by particle id, and a mass-spring body's springs with a torn one flagged.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>
#include <memory>
#include <set>

#include "demlink/core/deformable/mass_spring_body.hpp"
#include "demlink/server/view/frame_encoder.hpp"
#include "view_requests.hpp"

namespace demlink::server {
namespace {

template <class T>
T read(const std::vector<std::uint8_t>& bytes, std::size_t offset) {
  T value{};
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

std::size_t aligned(std::size_t offset) { return (offset + 3) & ~std::size_t{3}; }

/// n particles with ids shuffled over the slots, uniformly in [-1, 9] x [0, 2] x [0.5, 1.5] m.
ViewSnapshot randomSnapshot(std::size_t n, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  ViewSnapshot snapshot;
  snapshot.box_lower = {-1.0f, 0.0f, 0.5f};
  snapshot.box_upper = {9.0f, 2.0f, 1.5f};
  snapshot.id.resize(n);
  std::iota(snapshot.id.begin(), snapshot.id.end(), 1);
  std::shuffle(snapshot.id.begin(), snapshot.id.end(), random);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const float lower = snapshot.box_lower[axis], upper = snapshot.box_upper[axis];
      snapshot.position.push_back(lower + (upper - lower) * unit(random));
    }
    snapshot.radius.push_back(0.002f + 0.003f * unit(random));
    snapshot.speed.push_back(5.0f * unit(random));
    snapshot.material.push_back(static_cast<std::uint32_t>(i % 3));
  }
  snapshot.status.time = 1.25;
  snapshot.status.step = 125000;
  snapshot.status.particle_mass = 3.5;
  snapshot.meshes.push_back({{1.0f, 2.0f, 3.0f}, {0.0f, 0.0f, 0.6f, 0.8f}});
  return snapshot;
}

TEST(FrameEncoder, HeaderAndQuantisationBound) {
  const ViewSnapshot snapshot = randomSnapshot(5000, 1);
  FrameScratch scratch;
  std::vector<std::uint8_t> frame;
  encodeFrame(snapshot, FrameRequest{}, scratch, frame);
  ASSERT_GE(frame.size(), kFrameHeaderBytes);
  EXPECT_EQ(read<std::uint32_t>(frame, 0), kFrameMagic);
  EXPECT_EQ(read<double>(frame, 8), 1.25);
  EXPECT_EQ(read<double>(frame, 16), 125000.0);
  EXPECT_EQ(read<double>(frame, 40), 3.5);
  EXPECT_EQ(read<std::uint32_t>(frame, 72), 5000u);
  const std::uint32_t m = read<std::uint32_t>(frame, 76);
  ASSERT_EQ(m, 5000u);
  const float radiusMax = read<float>(frame, 104);
  const float colourMin = read<float>(frame, 108), colourMax = read<float>(frame, 112);
  EXPECT_EQ(radiusMax, *std::max_element(snapshot.radius.begin(), snapshot.radius.end()));
  EXPECT_EQ(colourMin, *std::min_element(snapshot.speed.begin(), snapshot.speed.end()));
  EXPECT_EQ(colourMax, *std::max_element(snapshot.speed.begin(), snapshot.speed.end()));

  const std::size_t positions = kFrameHeaderBytes;
  const std::size_t radii = aligned(positions + 6 * m);
  const std::size_t colours = aligned(radii + 2 * m);
  const std::size_t meshes = aligned(colours + 2 * m);
  double worstPosition = 0.0, worstRadius = 0.0, worstColour = 0.0;
  for (std::size_t i = 0; i < m; ++i) {  // every particle is sent, in slot order
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const double lower = snapshot.box_lower[axis], upper = snapshot.box_upper[axis];
      const double decoded = lower + read<std::uint16_t>(frame, positions + 2 * (3 * i + axis)) / 65535.0 * (upper - lower);
      // Rounding to the nearest of 65536 levels: at most half a level off.
      worstPosition = std::max(worstPosition, std::abs(decoded - snapshot.position[3 * i + axis]) / ((upper - lower) / 131070.0));
    }
    const double radius = read<std::uint16_t>(frame, radii + 2 * i) / 65535.0 * radiusMax;
    worstRadius = std::max(worstRadius, std::abs(radius - snapshot.radius[i]) / (radiusMax / 131070.0));
    const double speed = colourMin + read<std::uint16_t>(frame, colours + 2 * i) / 65535.0 * (colourMax - colourMin);
    worstColour = std::max(worstColour, std::abs(speed - snapshot.speed[i]) / ((colourMax - colourMin) / 131070.0));
  }
  // 1 is the bound; the margin is the float spacing of the values decoded and compared
  // (at most 2 % of half a level for these ranges).
  EXPECT_LE(worstPosition, 1.02);
  EXPECT_LE(worstRadius, 1.02);
  EXPECT_LE(worstColour, 1.02);
  EXPECT_GT(worstPosition, 0.5);  // the error is really near the bound (the test can see it)
  EXPECT_EQ(read<float>(frame, meshes), 1.0f);
  EXPECT_EQ(read<float>(frame, meshes + 20), 0.6f);
  EXPECT_EQ(frame.size(), meshes + 28);
}

std::set<std::uint64_t> idsSent(const ViewSnapshot& snapshot, std::size_t maxParticles) {
  std::vector<std::uint32_t> slots;
  std::vector<std::uint64_t> ranks;
  chooseSubset(snapshot.id, maxParticles, slots, ranks);
  EXPECT_TRUE(std::is_sorted(slots.begin(), slots.end()));
  std::set<std::uint64_t> ids;
  for (const std::uint32_t slot : slots) ids.insert(snapshot.id[slot]);
  EXPECT_EQ(ids.size(), slots.size());
  return ids;
}

TEST(FrameEncoder, SubsetIsStableById) {
  const ViewSnapshot a = randomSnapshot(20000, 2);
  const ViewSnapshot b = randomSnapshot(20000, 3);  // same ids, other slots and places
  const std::set<std::uint64_t> fromA = idsSent(a, 1000);
  EXPECT_EQ(fromA.size(), 1000u);
  EXPECT_EQ(fromA, idsSent(b, 1000));
  const std::set<std::uint64_t> smaller = idsSent(a, 300);
  EXPECT_EQ(smaller.size(), 300u);
  EXPECT_TRUE(std::includes(fromA.begin(), fromA.end(), smaller.begin(), smaller.end()));
  // Spread over the ids, not a block of them: each tenth of the id range holds ~100.
  std::array<int, 10> perTenth{};
  for (const std::uint64_t id : fromA) ++perTenth[(id - 1) * 10 / 20000];
  for (const int count : perTenth) EXPECT_NEAR(count, 100, 40);
  // No more asked than there is: everything.
  EXPECT_EQ(idsSent(a, 50000).size(), 20000u);
  EXPECT_TRUE(idsSent(a, 0).empty());
}

TEST(FrameEncoder, SubsetFrameCarriesTheCount) {
  const ViewSnapshot snapshot = randomSnapshot(3000, 4);
  FrameScratch scratch;
  std::vector<std::uint8_t> frame;
  FrameRequest request;
  request.max_particles = 700;
  request.colour = ColourField::kMaterial;
  encodeFrame(snapshot, request, scratch, frame);
  EXPECT_EQ(read<std::uint32_t>(frame, 72), 3000u);
  EXPECT_EQ(read<std::uint32_t>(frame, 76), 700u);
  EXPECT_EQ(read<std::uint32_t>(frame, 116), static_cast<std::uint32_t>(ColourField::kMaterial));
  EXPECT_EQ(read<float>(frame, 108), 0.0f);
  EXPECT_EQ(read<float>(frame, 112), 2.0f);
  const std::size_t capacity = frame.capacity();
  encodeFrame(snapshot, request, scratch, frame);  // the next frame reuses the buffer
  EXPECT_EQ(frame.capacity(), capacity);
}

TEST(FrameEncoder, Quantise) {
  EXPECT_EQ(quantise(-5.0, 0.0, 1.0), 0);
  EXPECT_EQ(quantise(5.0, 0.0, 1.0), 65535);
  EXPECT_EQ(quantise(0.5, 0.0, 1.0), 32768);
  EXPECT_EQ(quantise(1.0, 1.0, 1.0), 0);  // degenerate range
  EXPECT_EQ(quantise(std::nan(""), 0.0, 1.0), 0);
}

/// The surface sections of a frame whose header says it has no particles, meshes or regions.
struct DecodedSurface {
  std::vector<float> positions;
  std::vector<std::uint8_t> active, intact;
};
std::vector<DecodedSurface> decodeSurfaces(const std::vector<std::uint8_t>& frame) {
  EXPECT_EQ(read<std::uint32_t>(frame, 76) + read<std::uint32_t>(frame, 120) + read<std::uint32_t>(frame, 128), 0u);
  std::vector<DecodedSurface> out(read<std::uint32_t>(frame, 124));
  std::size_t offset = kFrameHeaderBytes;
  for (DecodedSurface& surface : out) {
    const std::uint32_t nodes = read<std::uint32_t>(frame, offset);
    const std::uint32_t triangles = read<std::uint32_t>(frame, offset + 4);
    const std::uint32_t springs = read<std::uint32_t>(frame, offset + 8);
    offset += 12;
    for (std::uint32_t k = 0; k < 3 * nodes; ++k, offset += 4) surface.positions.push_back(read<float>(frame, offset));
    surface.active.assign(frame.begin() + static_cast<std::ptrdiff_t>(offset),
                          frame.begin() + static_cast<std::ptrdiff_t>(offset + triangles));
    offset = aligned(offset + triangles);
    surface.intact.assign(frame.begin() + static_cast<std::ptrdiff_t>(offset),
                          frame.begin() + static_cast<std::ptrdiff_t>(offset + springs));
    offset = aligned(offset + springs);
  }
  EXPECT_EQ(offset, frame.size()) << "the surfaces end the frame";
  return out;
}

TEST(FrameEncoder, MassSpringBodyCarriesItsSpringsAndATornOneIsFlagged) {
  core::SimulationSettings settings;
  settings.gravity = core::Vec3::Zero();
  settings.time_step = 1.0e-4;
  core::World world(settings);
  core::Material material;
  material.name = "rubber";
  material.density = 1000.0;
  material.youngs_modulus = 1.0e6;
  material.poisson_ratio = 0.3;
  material.restitution = 0.5;
  const std::uint32_t rubber = world.addMaterial(material);
  // A triangle of springs whose first (nodes 0-1, 5 % over its rest length: 25 N) tears
  // at the first step's end (break force 10 N); the others are at rest and hold.
  core::MassSpringSpec spec;
  spec.name = "sheet";
  spec.material = rubber;
  spec.total_mass = 3.0;
  spec.nodes = {core::Vec3::Zero(), core::Vec3(1.05, 0.0, 0.0), core::Vec3(0.0, 1.0, 0.0)};
  spec.springs = {{0, 1, 500.0, 0.0, 1.0}, {1, 2, 500.0, 0.0, -1.0}, {0, 2, 500.0, 0.0, -1.0}};
  spec.triangles = {{0, 1, 2}};
  spec.break_force = 10.0;
  world.addDeformableBody(std::make_unique<core::MassSpringBody>(spec, "sheet"), "sheet");
  world.initialize();

  const std::string scene = describeScene(world);
  EXPECT_NE(scene.find(R"("name":"sheet","triangles":[0,1,2],"springs":[0,1,1,2,0,2]})"), std::string::npos)
      << scene;
  ViewSnapshot snapshot;
  FrameScratch scratch;
  std::vector<std::uint8_t> frame;
  captureSnapshot(world, {}, snapshot);
  encodeFrame(snapshot, FrameRequest{}, scratch, frame);
  EXPECT_EQ(read<std::uint32_t>(frame, 4), kFrameVersion);
  std::vector<DecodedSurface> surfaces = decodeSurfaces(frame);
  ASSERT_EQ(surfaces.size(), 1u);
  EXPECT_EQ(surfaces[0].intact, (std::vector<std::uint8_t>{1, 1, 1}));
  EXPECT_EQ(surfaces[0].active, (std::vector<std::uint8_t>{1}));
  ASSERT_EQ(surfaces[0].positions.size(), 9u);
  EXPECT_FLOAT_EQ(surfaces[0].positions[3], 1.05f);

  world.step();
  const auto& body = dynamic_cast<const core::MassSpringBody&>(*world.deformableBodies()[0]);
  ASSERT_EQ(body.brokenCount(), 1u) << "the test needs the first spring torn";
  captureSnapshot(world, {}, snapshot);
  encodeFrame(snapshot, FrameRequest{}, scratch, frame);
  surfaces = decodeSurfaces(frame);
  ASSERT_EQ(surfaces.size(), 1u);
  EXPECT_EQ(surfaces[0].intact, (std::vector<std::uint8_t>{0, 1, 1})) << "the torn spring is flagged, the others not";
  EXPECT_EQ(surfaces[0].active, (std::vector<std::uint8_t>{0})) << "the triangle along it lost its support";
  for (std::size_t k = 0; k < 9; ++k) {
    EXPECT_FLOAT_EQ(surfaces[0].positions[k], static_cast<float>(body.nodePosition(k / 3)[static_cast<int>(k % 3)]));
  }
}

TEST(ViewRequests, ParsesAndRefuses) {
  std::string error;
  const std::optional<ViewRequest> request = parseViewRequest("rate=12.5 max=2000;colour=force frame=7 sim=3", 30.0, error);
  ASSERT_TRUE(request.has_value()) << error;
  EXPECT_EQ(request->rate.value(), 12.5);
  EXPECT_EQ(request->max_particles.value(), 2000u);
  EXPECT_EQ(request->colour.value(), ColourField::kForce);
  EXPECT_EQ(request->frame.value(), 7u);
  EXPECT_EQ(request->simulation.value(), 3u);
  for (const char* bad : {"rate=0", "rate=31", "rate=nan", "max=-1", "max=20000000", "colour=blue", "frame=x",
                          "sim=0", "sim=-1", "sim=two", "sim=", "volume=3", "rate"}) {
    EXPECT_FALSE(parseViewRequest(bad, 30.0, error).has_value()) << bad;
    EXPECT_FALSE(error.empty());
  }
  EXPECT_FALSE(parseViewRequest("colour=blue", 30.0, error).has_value());
  EXPECT_NE(error.find("colour = \"blue\": one of speed, force, material, id"), std::string::npos) << error;
}

}  // namespace
}  // namespace demlink::server
