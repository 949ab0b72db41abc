// The view server with a live hub over loopback sockets: page files, the token, frames at the
// rate and particle budget a page asks for, the connection cap, and a stalled page that must
// not slow the simulation, and several simulations stepping at once, among which a page chooses.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <optional>
#include <regex>
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

/// n spheres in a row along x, no gravity, at rest.
core::World rowOfSpheres(std::size_t n) {
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
    spec.position = core::Vec3(0.01 * static_cast<double>(i), 0.0, 0.0);
    spec.radius = 0.004;
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

/// Two worlds of 30 and 50 spheres stepping on threads of their own until destroyed, each
/// announced under its name and offered after every step, as demlink-server's simulations.
struct TwoSimulations {
  core::World small = rowOfSpheres(30);
  core::World large = rowOfSpheres(50);
  std::atomic<bool> stop{false};
  std::thread a, b;

  explicit TwoSimulations(LiveViewHub& hub) {
    auto run = [this, &hub](core::World& world, const std::string& name) {
      hub.announce(world, name);
      while (!stop.load()) {
        world.step();
        hub.offer(world);
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
    };
    a = std::thread(run, std::ref(small), "sim_small");
    b = std::thread(run, std::ref(large), "sim_large");
  }
  ~TwoSimulations() {
    stop = true;
    a.join();
    b.join();
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

TEST(LiveViewHub, FollowsOneOfSeveralSimulationsSteppingAtOnce) {
  core::World first = rowOfSpheres(30);
  core::World second = rowOfSpheres(50);
  LiveViewHub hub;
  hub.setDemand(1000.0, {});
  // Both step on their own threads and offer every step; only one is ever captured.
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
  const ViewSnapshot* shown = hub.snapshot(0, version);
  ASSERT_NE(shown, nullptr);
  const core::World& followed = shown->particleCount() == 30 ? first : second;
  const core::World& other = &followed == &first ? second : first;
  const std::uint64_t sceneVersion = hub.sceneVersion();
  EXPECT_EQ(sceneVersion, 1u);  // described once: the view never switched back and forth
  // The other's offers change nothing while the followed one is open...
  const std::uint64_t captures = hub.captures();
  hub.offerNow(other);
  EXPECT_EQ(hub.captures(), captures);
  // ...releasing the other is no release; releasing the followed one hands the view over.
  hub.release(other);
  hub.offerNow(other);
  EXPECT_EQ(hub.captures(), captures);
  hub.release(followed);
  hub.offerNow(other);
  EXPECT_EQ(hub.captures(), captures + 1);
  EXPECT_EQ(hub.sceneVersion(), sceneVersion + 1);
  shown = hub.snapshot(0, version);
  ASSERT_NE(shown, nullptr);
  EXPECT_EQ(shown->particleCount(), &other == &first ? 30u : 50u);
}

TEST(LiveViewHub, FollowsTheSimulationAPageChooses) {
  LiveViewHub hub;
  hub.setDemand(1000.0, {});
  TwoSimulations simulations(hub);
  std::string list;
  for (int k = 0; k < 2000 && !(listed(list, "sim_small") && listed(list, "sim_large")); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    list = hub.simulationsJson();
  }
  ASSERT_TRUE(listed(list, "sim_small") && listed(list, "sim_large")) << list;
  EXPECT_EQ(listed(list, "sim_small")->second, 30u);
  EXPECT_EQ(listed(list, "sim_large")->second, 50u);
  // Each in turn, twice over: after the choice every snapshot is the chosen one's.
  for (const char* name : {"sim_small", "sim_large", "sim_small", "sim_large"}) {
    const auto [id, particles] = *listed(list, name);
    const std::uint64_t versionBefore = hub.simulationsVersion();
    const bool followedBefore = followedId(hub.simulationsJson()) == id;
    ASSERT_EQ(hub.follow(id), std::nullopt) << name;
    if (!followedBefore) {
      EXPECT_GT(hub.simulationsVersion(), versionBefore) << "the pages are sent the list again";
    }
    EXPECT_EQ(followedId(hub.simulationsJson()), id);
    std::uint64_t version = 0, first = 0;
    const ViewSnapshot* shown = nullptr;
    for (int k = 0; k < 2000; ++k) {  // the first capture after the choice
      shown = hub.snapshot(0, version);
      if (shown != nullptr && shown->particleCount() == particles) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_NE(shown, nullptr);
    ASSERT_EQ(shown->particleCount(), particles) << name;
    first = version;
    for (int k = 0; k < 50; ++k) {
      shown = hub.snapshot(0, version);
      EXPECT_EQ(shown->particleCount(), particles) << name;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    EXPECT_GT(version, first) << "the chosen simulation goes on being captured";
  }
  // An id no open simulation has is refused, and the view stays where it is.
  const std::uint64_t followed = followedId(hub.simulationsJson());
  const std::optional<std::string> refused = hub.follow(12345);
  ASSERT_TRUE(refused.has_value());
  EXPECT_NE(refused->find("no open simulation has this id (open: "), std::string::npos) << *refused;
  EXPECT_EQ(followedId(hub.simulationsJson()), followed);
}

TEST(LiveViewHub, ClosedSimulationLeavesTheList) {
  core::World first = rowOfSpheres(30);
  core::World second = rowOfSpheres(50);
  LiveViewHub hub;
  hub.announce(first, "sim_001");
  hub.offer(first);
  hub.offer(second);  // unnamed: listed by its id
  const std::string list = hub.simulationsJson();
  ASSERT_TRUE(listed(list, "sim_001")) << list;
  const std::uint64_t secondId = listed(list, "simulation " + std::to_string(listed(list, "sim_001")->first + 1))->first;
  EXPECT_EQ(followedId(list), listed(list, "sim_001")->first);  // the first to offer
  hub.release(first);
  const std::string after = hub.simulationsJson();
  EXPECT_FALSE(listed(after, "sim_001")) << after;
  EXPECT_EQ(followedId(after), 0u);
  EXPECT_TRUE(hub.follow(listed(list, "sim_001")->first).has_value()) << "a closed simulation cannot be chosen";
  EXPECT_EQ(hub.follow(secondId), std::nullopt);
  hub.offerNow(second);
  std::uint64_t version = 0;
  const ViewSnapshot* shown = hub.snapshot(0, version);
  ASSERT_NE(shown, nullptr);
  EXPECT_EQ(shown->particleCount(), 50u);
}

TEST(ViewServer, PageChoosesAmongSimulationsSteppingAtOnce) {
  LiveViewHub hub;
  ViewServer server(hub, {});
  server.start();
  TwoSimulations simulations(hub);
  Client client(server.port());
  client.send(upgrade("/ws"));
  client.readUntil("\r\n\r\n");
  client.send(encodeMaskedClientFrame(WebSocketOpcode::kText, "rate=30", {1, 2, 3, 4}));
  // Frames' particle totals and the latest list, message by message.
  std::string list, error;
  auto nextTotal = [&]() -> std::uint32_t {
    for (;;) {
      const auto [opcode, payload] = client.readFrame();
      if (opcode == 1 && payload.find(R"("kind":"simulations")") != std::string::npos) list = payload;
      if (opcode == 1 && payload.find(R"("kind":"error")") != std::string::npos) error = payload;
      if (opcode != 2) continue;
      std::uint32_t total = 0;
      std::memcpy(&total, payload.data() + 72, 4);
      return total;
    }
  };
  for (int k = 0; k < 200 && !(listed(list, "sim_small") && listed(list, "sim_large")); ++k) nextTotal();
  ASSERT_TRUE(listed(list, "sim_small") && listed(list, "sim_large")) << list;
  for (const char* name : {"sim_small", "sim_large"}) {
    const auto [id, particles] = *listed(list, name);
    client.send(encodeMaskedClientFrame(WebSocketOpcode::kText, "sim=" + std::to_string(id), {9, 8, 7, 6}));
    int frames = 0;
    while (frames < 200 && nextTotal() != particles) ++frames;
    ASSERT_LT(frames, 200) << "no frame of " << name << " after choosing it";
    for (int k = 0; k < 10; ++k) EXPECT_EQ(nextTotal(), particles) << name;
    while (followedId(list) != id && frames++ < 400) nextTotal();
    EXPECT_EQ(followedId(list), id) << list;
  }
  // An unknown id gets a named error; the page keeps its connection and its simulation.
  client.send(encodeMaskedClientFrame(WebSocketOpcode::kText, "sim=999", {1, 1, 1, 1}));
  for (int k = 0; k < 200 && error.empty(); ++k) nextTotal();
  EXPECT_NE(error.find(R"(sim = \"999\": no open simulation has this id (open: )"), std::string::npos) << error;
  for (int k = 0; k < 5; ++k) EXPECT_EQ(nextTotal(), 50u);
}

}  // namespace
}  // namespace demlink::server
