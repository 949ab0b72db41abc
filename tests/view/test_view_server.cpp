// The view server with a live hub over loopback sockets: page files, the token, frames at the
// rate and particle budget a page asks for, the connection cap, and a stalled page that must
// not slow the simulation, and several simulations stepping at once, among which a page chooses.
#include <gtest/gtest.h>
#include <poll.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <optional>
#include <regex>
#include <stdexcept>
#include <string>
#include <thread>

#include "demlink/server/net/asio.hpp"
#include "demlink/server/view/frame_encoder.hpp"
#include "demlink/server/view/live_view_hub.hpp"
#include "demlink/server/view/view_server.hpp"
#include "demlink/server/view/websocket.hpp"

namespace demlink::server {
namespace {

using asio::ip::tcp;

/// Where the two simulations' rows lie, so that a frame tells whose it is by its box too [m].
constexpr double kSmallY = 0.0;
constexpr double kLargeY = 0.5;
/// Sphere radius of rowOfSpheres [m].
constexpr double kRadius = 0.004;

/// n spheres in a row along x at height y, no gravity, at rest.
core::World rowOfSpheres(std::size_t n, double y = 0.0) {
  core::SimulationSettings settings;
  settings.gravity = core::Vec3::Zero();
  settings.time_step = 1.0e-5;
  core::World world(settings);
  core::Material material;
  material.name = "glass";
  material.density = 2500.0;
  material.youngs_modulus = 1.0e7;
  material.poisson_ratio = 0.3;
  material.restitution = 0.5;
  const std::uint32_t glass = world.addMaterial(material);
  for (std::size_t i = 0; i < n; ++i) {
    core::ParticleSpec spec;
    spec.position = core::Vec3(0.01 * static_cast<double>(i), y, 0.0);
    spec.radius = kRadius;
    spec.material = glass;
    world.addParticle(spec);
  }
  world.initialize();
  return world;
}

struct Client {
  asio::io_context io;
  tcp::socket socket{io};

  explicit Client(std::uint16_t port) { socket.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port)); }
  void send(const std::string& bytes) { asio::write(socket, asio::buffer(bytes)); }
  /// Everything until the server closes.
  std::string readAll() {
    std::string out;
    asio::error_code error;
    std::array<char, 65536> buffer{};
    while (!error) {
      const std::size_t n = socket.read_some(asio::buffer(buffer), error);
      out.append(buffer.data(), n);
    }
    return out;
  }
  std::string readUntil(const std::string& marker) {
    std::string out;
    while (out.find(marker) == std::string::npos) {
      char c = 0;
      asio::read(socket, asio::buffer(&c, 1));
      out += c;
    }
    return out;
  }
  /// Whether data arrives within `seconds` (a test that waits in vain fails instead of hanging).
  bool readable(double seconds) {
    pollfd poll_fd{socket.native_handle(), POLLIN, 0};
    return ::poll(&poll_fd, 1, static_cast<int>(seconds * 1000.0)) > 0;
  }
  /// One server frame: opcode and payload.
  std::pair<int, std::string> readFrame() {
    std::uint8_t head[2];
    asio::read(socket, asio::buffer(head));
    std::uint64_t length = head[1] & 0x7F;
    if (length == 126) {
      std::uint8_t ext[2];
      asio::read(socket, asio::buffer(ext));
      length = (std::uint64_t{ext[0]} << 8) | ext[1];
    } else if (length == 127) {
      std::uint8_t ext[8];
      asio::read(socket, asio::buffer(ext));
      length = 0;
      for (const std::uint8_t b : ext) length = (length << 8) | b;
    }
    EXPECT_EQ(head[1] & 0x80, 0) << "server frames are never masked";
    std::string payload(static_cast<std::size_t>(length), '\0');
    asio::read(socket, asio::buffer(payload));
    return {head[0] & 0x0F, payload};
  }
};

/// The id a "simulations" message gives the simulation called `name`, and its particle count.
std::optional<std::pair<std::uint64_t, std::uint64_t>> listed(const std::string& list, const std::string& name) {
  std::smatch match;
  const std::regex entry(R"re("id":(\d+),"name":")re" + name + R"re(","particles":(\d+),"time":)re");
  if (!std::regex_search(list, match, entry)) return std::nullopt;
  return std::pair{std::stoull(match[1].str()), std::stoull(match[2].str())};
}

std::uint64_t followedId(const std::string& list) {
  std::smatch match;
  if (!std::regex_search(list, match, std::regex(R"re("followed":(\d+))re"))) return 0;
  return std::stoull(match[1].str());
}

/// Two worlds, of 30 spheres at y = kSmallY and 50 at y = kLargeY, stepping on threads of
/// their own until closed, each announced under its name, offered after every step and
/// released at its end, as demlink-server's simulations. The small one steps first, so it
/// is the default.
struct TwoSimulations {
  core::World small = rowOfSpheres(30, kSmallY);
  core::World large = rowOfSpheres(50, kLargeY);
  std::atomic<bool> stop_small{false}, stop_large{false};
  std::thread a, b;

  explicit TwoSimulations(LiveViewHub& hub) {
    auto run = [&hub](core::World& world, const std::string& name, const std::atomic<bool>& stop) {
      hub.announce(world, name);
      while (!stop.load()) {
        world.step();
        hub.offer(world);
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
      hub.release(world);
    };
    a = std::thread(run, std::ref(small), "sim_small", std::cref(stop_small));
    for (int k = 0; k < 5000 && followedId(hub.simulationsJson(kDefaultSimulation)) == 0; ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    b = std::thread(run, std::ref(large), "sim_large", std::cref(stop_large));
  }
  /// Stops the large one; its thread releases it.
  void closeLarge() {
    stop_large = true;
    b.join();
  }
  ~TwoSimulations() {
    stop_small = true;
    stop_large = true;
    if (a.joinable()) a.join();
    if (b.joinable()) b.join();
  }
};

std::string get(std::uint16_t port, const std::string& target) {
  Client client(port);
  client.send("GET " + target + " HTTP/1.1\r\nHost: x\r\n\r\n");
  return client.readAll();
}

std::string upgrade(const std::string& target) {
  return "GET " + target + " HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
         "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";
}

/// One page over a WebSocket at 30 frames/s: what its frames show, and the latest list,
/// error and scene count among the text messages in between.
struct Page {
  Client client;
  std::string list, error;
  int scenes = 0;

  explicit Page(std::uint16_t port) : client(port) {
    client.send(upgrade("/ws"));
    client.readUntil("\r\n\r\n");
    ask("rate=30");
  }
  void ask(const std::string& request) {
    client.send(encodeMaskedClientFrame(WebSocketOpcode::kText, request, {9, 8, 7, 6}));
  }
  struct Shown {
    std::uint32_t particles = 0;  ///< in the world
    float lower_y = 0.0f;         ///< the box's lower y [m]
  };
  Shown nextFrame() {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    for (;;) {
      const double left = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
      if (left <= 0.0 || !client.readable(left)) throw std::runtime_error("the page got no frame for 10 s");
      const auto [opcode, payload] = client.readFrame();
      if (opcode == 1 && payload.find(R"("kind":"simulations")") != std::string::npos) list = payload;
      if (opcode == 1 && payload.find(R"("kind":"error")") != std::string::npos) error = payload;
      if (opcode == 1 && payload.find(R"("kind":"scene")") != std::string::npos) ++scenes;
      if (opcode != 2) continue;
      Shown shown;
      std::memcpy(&shown.particles, payload.data() + 72, 4);
      std::memcpy(&shown.lower_y, payload.data() + 84, 4);
      return shown;
    }
  }
  /// Reads frames until one of `particles` arrives; false when none among the next 300.
  bool awaitFrameOf(std::uint32_t particles) {
    for (int k = 0; k < 300; ++k) {
      if (nextFrame().particles == particles) return true;
    }
    return false;
  }
  /// Reads frames until the list says the page follows `id`; false when not within 300.
  bool awaitFollowing(std::uint64_t id) {
    for (int k = 0; k < 300 && followedId(list) != id; ++k) nextFrame();
    return followedId(list) == id;
  }
  /// The next `count` frames are all of the simulation with `particles` at row height `y`.
  void expectFramesOf(std::uint32_t particles, double y, int count, const std::string& what) {
    for (int k = 0; k < count; ++k) {
      const Shown shown = nextFrame();
      EXPECT_EQ(shown.particles, particles) << what;
      EXPECT_NEAR(shown.lower_y, y - kRadius, 1.0e-6) << what;
    }
  }
};

TEST(ViewServer, ServesThePageAndOnlyThreeJsFromItsFolder) {
  LiveViewHub hub;
  ViewServer server(hub, {});
  server.start();
  const std::string page = get(server.port(), "/");
  EXPECT_TRUE(page.starts_with("HTTP/1.1 200 OK\r\n")) << page.substr(0, 80);
  EXPECT_NE(page.find("text/html"), std::string::npos);
  EXPECT_NE(page.find("<script type=\"module\" src=\"view.js\">"), std::string::npos);
  EXPECT_TRUE(get(server.port(), "/view.js").starts_with("HTTP/1.1 200 OK\r\n"));
  if (std::filesystem::exists("/usr/share/javascript/three/build/three.module.js")) {
    const std::string three = get(server.port(), "/three/build/three.module.js");
    EXPECT_TRUE(three.starts_with("HTTP/1.1 200 OK\r\n"));
    EXPECT_NE(three.find("REVISION"), std::string::npos);
  }
  EXPECT_TRUE(get(server.port(), "/three/../../../etc/passwd").starts_with("HTTP/1.1 404"));
  EXPECT_TRUE(get(server.port(), "/three/%2e%2e/%2e%2e/etc/hostname.js").starts_with("HTTP/1.1 404"));
  EXPECT_TRUE(get(server.port(), "/secret").starts_with("HTTP/1.1 404"));
  Client post(server.port());
  post.send("POST / HTTP/1.1\r\nContent-Length: 0\r\n\r\n");
  EXPECT_TRUE(post.readAll().starts_with("HTTP/1.1 405"));
}

TEST(ViewServer, WebSocketNeedsTheTokenWhenOneIsSet) {
  LiveViewHub hub;
  ViewServerOptions options;
  options.access_token = "s3cret";
  ViewServer server(hub, options);
  server.start();
  for (const char* target : {"/ws", "/ws?token=wrong", "/ws?token=s3cre", "/ws?token=s3cret2"}) {
    Client client(server.port());
    client.send(upgrade(target));
    const std::string answer = client.readAll();
    EXPECT_TRUE(answer.starts_with("HTTP/1.1 403")) << target;
    EXPECT_EQ(answer.find("s3cret"), std::string::npos) << "the token is never echoed";
  }
  Client client(server.port());
  client.send(upgrade("/ws?token=s3cret"));
  EXPECT_NE(client.readUntil("\r\n\r\n").find("101 Switching Protocols"), std::string::npos);
}

TEST(ViewServer, StreamsFramesAtThePagesBudget) {
  core::World world = rowOfSpheres(40);
  LiveViewHub hub;
  ViewServer server(hub, {});
  server.start();
  hub.offer(world);  // the scene and a first snapshot
  Client client(server.port());
  client.send(upgrade("/ws"));
  const std::string response = client.readUntil("\r\n\r\n");
  ASSERT_NE(response.find("Sec-WebSocket-Accept: s3pPLMBiTxaQ9kYGzzhZRbK+xOo="), std::string::npos);
  const auto [sceneOpcode, scene] = client.readFrame();
  EXPECT_EQ(sceneOpcode, 1);
  EXPECT_NE(scene.find("\"materials\":[\"glass\"]"), std::string::npos) << scene;
  const auto [helloOpcode, hello] = client.readFrame();
  EXPECT_NE(hello.find("\"live\":true"), std::string::npos) << hello;
  client.send(encodeMaskedClientFrame(WebSocketOpcode::kText, "rate=30 max=15 colour=id", {5, 6, 7, 8}));
  // The simulation steps on; frames come at the page's rate with its budget.
  std::thread stepper([&] {
    for (int k = 0; k < 200; ++k) {
      world.step();
      hub.offer(world);
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });
  std::uint32_t total = 0, sent = 0, colour = 99;
  std::string list;
  for (int k = 0; k < 3;) {  // the first may predate the request
    const auto [opcode, frame] = client.readFrame();
    if (opcode == 1) {  // the list of simulations: this one alone
      list = frame;
      continue;
    }
    ++k;
    ASSERT_EQ(opcode, 2);
    ASSERT_GE(frame.size(), kFrameHeaderBytes);
    std::memcpy(&total, frame.data() + 72, 4);
    std::memcpy(&sent, frame.data() + 76, 4);
    std::memcpy(&colour, frame.data() + 116, 4);
  }
  stepper.join();
  EXPECT_NE(list.find(R"("simulations":[{"id":1,"name":"simulation 1","particles":40,"time":)"), std::string::npos)
      << list;
  EXPECT_EQ(total, 40u);
  EXPECT_EQ(sent, 15u);
  EXPECT_EQ(colour, static_cast<std::uint32_t>(ColourField::kId));
  // A bad request gets a named error and the connection stays.
  client.send(encodeMaskedClientFrame(WebSocketOpcode::kText, "rate=1000", {1, 2, 3, 4}));
  for (int k = 0; k < 20; ++k) {
    const auto [opcode, payload] = client.readFrame();
    if (opcode != 1) continue;
    EXPECT_NE(payload.find(R"("kind":"error","message":"rate = \"1000\": )"), std::string::npos) << payload;
    break;
  }
}

TEST(ViewServer, RefusesConnectionsOverTheCap) {
  LiveViewHub hub;
  ViewServerOptions options;
  options.max_connections = 2;
  ViewServer server(hub, options);
  server.start();
  Client first(server.port()), second(server.port());  // both idle in their request phase
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_TRUE(get(server.port(), "/").starts_with("HTTP/1.1 503"));
}

TEST(ViewServer, StalledPageNeverSlowsTheSimulation) {
  core::World world = rowOfSpheres(20000);
  LiveViewHub hub;
  ViewServer server(hub, {});
  server.start();
  hub.offer(world);
  Client stalled(server.port());  // asks for 30 frames/s of ~200 kB, then reads nothing
  stalled.send(upgrade("/ws"));
  stalled.readUntil("\r\n\r\n");
  stalled.send(encodeMaskedClientFrame(WebSocketOpcode::kText, "rate=30", {1, 2, 3, 4}));
  using Clock = std::chrono::steady_clock;
  double slowestOffer = 0.0;
  const Clock::time_point start = Clock::now();
  std::uint64_t sentAtHalf = 0;
  while (Clock::now() - start < std::chrono::seconds(4)) {
    const Clock::time_point before = Clock::now();
    hub.offer(world);
    slowestOffer = std::max(slowestOffer, std::chrono::duration<double>(Clock::now() - before).count());
    if (sentAtHalf == 0 && Clock::now() - start > std::chrono::seconds(2)) sentAtHalf = server.framesSent();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  // Captures go on at the page's rate whatever the page reads...
  EXPECT_GT(hub.captures(), 60u);
  // ...a capture is a copy, never a wait on the network (20,000 particles: well under 50 ms)...
  EXPECT_LT(slowestOffer, 0.05);
  // ...and once the socket's buffers are full no further frame goes out (one in flight).
  EXPECT_LE(server.framesSent() - sentAtHalf, 1u);
  EXPECT_LT(server.framesSent(), hub.captures());
}

/// Waits until the hub lists both simulations; their ids and particle counts.
std::pair<std::pair<std::uint64_t, std::uint64_t>, std::pair<std::uint64_t, std::uint64_t>> bothListed(
    LiveViewHub& hub) {
  std::string list;
  for (int k = 0; k < 5000 && !(listed(list, "sim_small") && listed(list, "sim_large")); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    list = hub.simulationsJson(kDefaultSimulation);
  }
  if (!(listed(list, "sim_small") && listed(list, "sim_large"))) {
    ADD_FAILURE() << "not both listed: " << list;
    return {};
  }
  return {*listed(list, "sim_small"), *listed(list, "sim_large")};
}

/// The snapshot of `simulation` once one with `particles` is there (null when none comes).
const ViewSnapshot* awaitSnapshot(LiveViewHub& hub, SimulationId simulation, std::size_t particles,
                                  std::uint64_t& version) {
  for (int k = 0; k < 5000; ++k) {
    const ViewSnapshot* shown = hub.snapshot(simulation, 0, version);
    if (shown != nullptr && shown->particleCount() == particles) return shown;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return nullptr;
}

TEST(LiveViewHub, DefaultIsTheFirstToStepUntilItCloses) {
  core::World first = rowOfSpheres(30);
  core::World second = rowOfSpheres(50);
  LiveViewHub hub;
  hub.setDemand({{kDefaultSimulation, 1000.0, {}}});
  // Both step on their own threads and offer every step; pages follow the default only, so
  // only the default is ever captured.
  std::atomic<bool> go{false};
  auto stepAndOffer = [&](core::World& world) {
    while (!go.load()) std::this_thread::yield();
    for (int k = 0; k < 300; ++k) {
      world.step();
      hub.offer(world);
    }
  };
  std::thread a(stepAndOffer, std::ref(first)), b(stepAndOffer, std::ref(second));
  go = true;
  a.join();
  b.join();
  std::uint64_t version = 0;
  const ViewSnapshot* shown = hub.snapshot(kDefaultSimulation, 0, version);
  ASSERT_NE(shown, nullptr);
  const core::World& followed = shown->particleCount() == 30 ? first : second;
  const core::World& other = &followed == &first ? second : first;
  const std::uint64_t sceneVersion = hub.sceneVersion(kDefaultSimulation);
  EXPECT_GT(sceneVersion, 0u);
  // The other's offers capture nothing: no page follows it...
  const std::uint64_t captures = hub.captures();
  hub.offerNow(other);
  EXPECT_EQ(hub.captures(), captures);
  // ...releasing it changes nothing; releasing the default makes the next to offer the default.
  hub.release(other);
  hub.offerNow(other);
  EXPECT_EQ(hub.captures(), captures);
  hub.release(followed);
  hub.offerNow(other);
  EXPECT_EQ(hub.captures(), captures + 1);
  EXPECT_NE(hub.sceneVersion(kDefaultSimulation), sceneVersion);
  shown = hub.snapshot(kDefaultSimulation, 0, version);
  ASSERT_NE(shown, nullptr);
  EXPECT_EQ(shown->particleCount(), &other == &first ? 30u : 50u);
}

TEST(LiveViewHub, CapturesEachFollowedSimulationApart) {
  LiveViewHub hub;
  TwoSimulations simulations(hub);
  const auto [small, large] = bothListed(hub);
  ASSERT_NE(small.first, 0u);
  EXPECT_EQ(small.second, 30u);
  EXPECT_EQ(large.second, 50u);
  // No page: the default is captured once (its scene for the first page), the other never.
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::uint64_t version = 0;
  EXPECT_EQ(hub.snapshot(large.first, 0, version), nullptr);
  EXPECT_EQ(hub.sceneVersion(large.first), 0u);
  EXPECT_EQ(hub.captureSets(), 1u);
  ASSERT_NE(awaitSnapshot(hub, kDefaultSimulation, 30, version), nullptr);
  // Pages follow each: each is captured into its own buffers, at its pages' rate; one set
  // per simulation however many pages follow it, by its id or as the default.
  hub.setDemand({{kDefaultSimulation, 1000.0, {}}, {large.first, 10.0, {}}, {large.first, 1000.0, {}},
                 {small.first, 10.0, {}}});
  EXPECT_EQ(hub.captureSets(), 2u);
  ASSERT_NE(awaitSnapshot(hub, large.first, 50, version), nullptr);
  std::uint64_t firstLarge = version, firstSmall = 0;
  ASSERT_NE(awaitSnapshot(hub, kDefaultSimulation, 30, firstSmall), nullptr);
  std::uint64_t lastLarge = firstLarge, lastSmall = firstSmall;
  for (int k = 0; k < 50; ++k) {
    const ViewSnapshot* shown = hub.snapshot(large.first, 0, lastLarge);
    ASSERT_NE(shown, nullptr);
    EXPECT_EQ(shown->particleCount(), 50u);
    EXPECT_FLOAT_EQ(shown->position[1], static_cast<float>(kLargeY));
    shown = hub.snapshot(kDefaultSimulation, 0, lastSmall);
    ASSERT_NE(shown, nullptr);
    EXPECT_EQ(shown->particleCount(), 30u);
    EXPECT_FLOAT_EQ(shown->position[1], static_cast<float>(kSmallY));
    shown = hub.snapshot(small.first, 0, version);  // the default by its id: the same
    ASSERT_NE(shown, nullptr);
    EXPECT_EQ(shown->particleCount(), 30u);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_GT(lastLarge, firstLarge) << "the large one goes on being captured";
  EXPECT_GT(lastSmall, firstSmall) << "the small one goes on being captured";
  EXPECT_NE(hub.sceneVersion(large.first), hub.sceneVersion(kDefaultSimulation));
  EXPECT_EQ(hub.sceneVersion(small.first), hub.sceneVersion(kDefaultSimulation));
  // Each page's list says which it follows.
  EXPECT_EQ(followedId(hub.simulationsJson(large.first)), large.first);
  EXPECT_EQ(followedId(hub.simulationsJson(kDefaultSimulation)), small.first);
  // The large one's pages leave: its captures are dropped, the default's stay.
  hub.setDemand({{kDefaultSimulation, 1000.0, {}}});
  EXPECT_EQ(hub.captureSets(), 1u);
  EXPECT_EQ(hub.snapshot(large.first, 0, version), nullptr);
  EXPECT_EQ(hub.sceneVersion(large.first), 0u);
  EXPECT_NE(hub.snapshot(kDefaultSimulation, 0, version), nullptr);
  // Any open simulation may be followed; an id no open simulation has is refused.
  EXPECT_EQ(hub.cannotFollow(large.first), std::nullopt);
  EXPECT_EQ(hub.cannotFollow(small.first), std::nullopt);
  const std::optional<std::string> refused = hub.cannotFollow(12345);
  ASSERT_TRUE(refused.has_value());
  EXPECT_NE(refused->find("no open simulation has this id (open: " + std::to_string(small.first) + ", " +
                          std::to_string(large.first) + ")"),
            std::string::npos)
      << *refused;
}

TEST(LiveViewHub, ClosedSimulationLeavesTheList) {
  core::World first = rowOfSpheres(30);
  core::World second = rowOfSpheres(50);
  LiveViewHub hub;
  hub.announce(first, "sim_001");
  hub.offer(first);
  hub.offer(second);  // unnamed: listed by its id
  const std::string list = hub.simulationsJson(kDefaultSimulation);
  ASSERT_TRUE(listed(list, "sim_001")) << list;
  const std::uint64_t firstId = listed(list, "sim_001")->first;
  const std::uint64_t secondId = listed(list, "simulation " + std::to_string(firstId + 1))->first;
  EXPECT_EQ(followedId(list), firstId);  // the first to offer is the default
  hub.setDemand({{firstId, 10.0, {}}, {secondId, 10.0, {}}});
  hub.offerNow(second);
  std::uint64_t version = 0;
  ASSERT_NE(hub.snapshot(secondId, 0, version), nullptr);
  hub.release(first);
  const std::string after = hub.simulationsJson(kDefaultSimulation);
  EXPECT_FALSE(listed(after, "sim_001")) << after;
  EXPECT_EQ(followedId(after), 0u) << "no default until the next offers";
  EXPECT_EQ(followedId(hub.simulationsJson(firstId)), 0u) << "a closed simulation's page is shown the default";
  EXPECT_TRUE(hub.cannotFollow(firstId).has_value()) << "a closed simulation cannot be followed";
  EXPECT_EQ(hub.snapshot(firstId, 0, version), nullptr);
  EXPECT_EQ(hub.cannotFollow(secondId), std::nullopt);
  hub.offerNow(second);
  EXPECT_EQ(followedId(hub.simulationsJson(kDefaultSimulation)), secondId);
  const ViewSnapshot* shown = hub.snapshot(kDefaultSimulation, 0, version);
  ASSERT_NE(shown, nullptr);
  EXPECT_EQ(shown->particleCount(), 50u);
  // Closed, the second's captures go too.
  hub.release(second);
  EXPECT_EQ(hub.captureSets(), 0u);
  EXPECT_EQ(hub.snapshot(secondId, 0, version), nullptr);
  EXPECT_EQ(hub.snapshot(kDefaultSimulation, 0, version), nullptr);
}

TEST(ViewServer, PageChoosesAmongSimulationsSteppingAtOnce) {
  LiveViewHub hub;
  ViewServer server(hub, {});
  server.start();
  TwoSimulations simulations(hub);
  Page page(server.port());
  for (int k = 0; k < 200 && !(listed(page.list, "sim_small") && listed(page.list, "sim_large")); ++k) {
    page.nextFrame();
  }
  ASSERT_TRUE(listed(page.list, "sim_small") && listed(page.list, "sim_large")) << page.list;
  for (const char* name : {"sim_large", "sim_small", "sim_large"}) {
    const auto [id, particles] = *listed(page.list, name);
    page.ask("sim=" + std::to_string(id));
    ASSERT_TRUE(page.awaitFrameOf(static_cast<std::uint32_t>(particles))) << "no frame of " << name;
    page.expectFramesOf(static_cast<std::uint32_t>(particles), particles == 30 ? kSmallY : kLargeY, 10, name);
    EXPECT_TRUE(page.awaitFollowing(id)) << page.list;
  }
  // An unknown id gets a named error; the page keeps its connection and its simulation.
  page.ask("sim=999");
  for (int k = 0; k < 200 && page.error.empty(); ++k) page.nextFrame();
  EXPECT_NE(page.error.find(R"(sim = \"999\": no open simulation has this id (open: )"), std::string::npos)
      << page.error;
  page.expectFramesOf(50, kLargeY, 5, "after the refused id");
}

TEST(ViewServer, EachPageFollowsItsOwnSimulation) {
  LiveViewHub hub;
  ViewServer server(hub, {});
  server.start();
  TwoSimulations simulations(hub);
  const auto [small, large] = bothListed(hub);
  Page a(server.port()), b(server.port());
  // a follows the default (the small one) without choosing; b chooses the large one.
  b.ask("sim=" + std::to_string(large.first));
  ASSERT_TRUE(b.awaitFrameOf(50));
  EXPECT_TRUE(b.awaitFollowing(large.first)) << b.list;
  b.expectFramesOf(50, kLargeY, 10, "b chose the large one");
  a.expectFramesOf(30, kSmallY, 10, "a stays on the default while b follows another");
  EXPECT_TRUE(a.awaitFollowing(small.first)) << a.list;
  // a chooses the large one too, then b the small one: neither choice moves the other page.
  a.ask("sim=" + std::to_string(large.first));
  ASSERT_TRUE(a.awaitFrameOf(50));
  a.expectFramesOf(50, kLargeY, 10, "a chose the large one");
  b.ask("sim=" + std::to_string(small.first));
  ASSERT_TRUE(b.awaitFrameOf(30));
  b.expectFramesOf(30, kSmallY, 10, "b chose the small one");
  EXPECT_TRUE(b.awaitFollowing(small.first)) << b.list;
  a.expectFramesOf(50, kLargeY, 10, "a stays on the large one while b follows the small one");
  EXPECT_TRUE(a.awaitFollowing(large.first)) << a.list;
  EXPECT_EQ(hub.captureSets(), 2u) << "one set of buffers per simulation followed";
}

TEST(ViewServer, PageOfAClosedSimulationMovesToTheDefault) {
  LiveViewHub hub;
  ViewServer server(hub, {});
  server.start();
  TwoSimulations simulations(hub);
  const auto [small, large] = bothListed(hub);
  Page a(server.port()), b(server.port());
  b.ask("sim=" + std::to_string(large.first));
  ASSERT_TRUE(b.awaitFrameOf(50));
  b.expectFramesOf(50, kLargeY, 5, "b chose the large one");
  const int scenesBefore = b.scenes;
  simulations.closeLarge();
  // b is told: its list no longer has the large one and says it follows the default, whose
  // scene and frames follow.
  EXPECT_TRUE(b.awaitFollowing(small.first)) << b.list;
  EXPECT_FALSE(listed(b.list, "sim_large")) << b.list;
  ASSERT_TRUE(b.awaitFrameOf(30));
  EXPECT_GT(b.scenes, scenesBefore) << "the default's scene is sent before its frames";
  b.expectFramesOf(30, kSmallY, 10, "b moved to the default");
  a.expectFramesOf(30, kSmallY, 10, "a stays on the default");
  EXPECT_EQ(hub.captureSets(), 1u) << "the closed one's buffers are gone";
  // b may choose again among the open ones; the closed id is refused.
  b.ask("sim=" + std::to_string(large.first));
  for (int k = 0; k < 200 && b.error.empty(); ++k) b.nextFrame();
  EXPECT_NE(b.error.find("no open simulation has this id (open: " + std::to_string(small.first) + ")"),
            std::string::npos)
      << b.error;
}

}  // namespace
}  // namespace demlink::server
