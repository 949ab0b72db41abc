/// demlink-bench-view: what the live view costs a running simulation.
///
/// One bed of `--particles` spheres (default 100,000) falling onto a floor, with a view
/// server and a page (a loopback client thread reading every frame it is sent) that asks
/// for `--rate` frames/s (default 10). Blocks of `--block-steps` steps (default 20) alternate
/// A B A B ... `--pairs` times (default 7): A steps without offering the world to the view,
/// B offers it after every step (LiveViewHub::offer, which copies a snapshot when a frame is
/// due). Printed: median thread-CPU seconds per step of A and B and their ratio, the median
/// ratio of neighbouring A, B blocks, the share of B's time spent inside offer(), and the
/// frames' bytes per particle. CPU time of the stepping thread: the view's encoding and
/// sending run on the view's own thread.
/// With `--serve S` it instead serves the bed, unstepped, for S seconds to a page opened
/// elsewhere (bench/view_page_fps.mjs measures the page's drawing rate against it), with a
/// new capture whenever a page wants a frame.
/// Usage: demlink-bench-view [--particles N] [--rate R] [--pairs K] [--block-steps S] [--serve S]
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>
#include <thread>
#include <vector>

#include "demlink/cli/command_line.hpp"
#include "demlink/server/net/asio.hpp"
#include "demlink/server/view/live_view_hub.hpp"
#include "demlink/server/view/view_server.hpp"
#include "demlink/server/view/websocket.hpp"

namespace {

using namespace demlink;

double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/// `initialize`: false for serving only (a million spheres' neighbour lists are not needed
/// to draw them).
core::World bed(std::size_t particles, bool initialize = true) {
  core::SimulationSettings settings;
  settings.time_step = 2e-6;
  settings.allow_unsafe_time_step = true;  // the cost, not the accuracy, is measured here
  core::World world(settings);
  core::Material material;
  material.name = "grains";
  world.addMaterial(material);
  world.addPlane({"floor", core::Vec3::Zero(), core::Vec3::UnitZ(), 0});
  const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(particles) / 20.0)));
  std::mt19937_64 random(1);
  std::uniform_real_distribution<double> jitter(-0.0004, 0.0004);
  for (std::size_t k = 0; k < particles; ++k) {
    core::ParticleSpec spec;
    spec.radius = 0.002;
    spec.position = core::Vec3(0.0045 * static_cast<double>(k % side) + jitter(random),
                               0.0045 * static_cast<double>((k / side) % side) + jitter(random),
                               0.003 + 0.0045 * static_cast<double>(k / (side * side)));
    world.addParticle(spec);
  }
  if (initialize) world.initialize();
  return world;
}

/// A page: handshake, one request, then reads frames until stopped.
struct Page {
  std::atomic<std::uint64_t> frames{0};
  std::atomic<std::uint64_t> last_frame_bytes{0};
  std::atomic<bool> stop{false};
  std::thread thread;

  Page(std::uint16_t port, double rate) {
    thread = std::thread([this, port, rate] {
      asio::io_context io;
      asio::ip::tcp::socket socket(io);
      socket.connect({asio::ip::make_address("127.0.0.1"), port});
      asio::write(socket, asio::buffer(std::string(
                              "GET /ws HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                              "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n")));
      std::string head;  // byte by byte: nothing after the handshake response is consumed
      while (!head.ends_with("\r\n\r\n")) {
        char c = 0;
        asio::read(socket, asio::buffer(&c, 1));
        head += c;
      }
      asio::write(socket, asio::buffer(server::encodeMaskedClientFrame(
                              server::WebSocketOpcode::kText, "rate=" + std::to_string(rate), {1, 2, 3, 4})));
      std::vector<char> payload;
      asio::error_code error;
      while (!stop && !error) {
        std::uint8_t bytes[10];
        asio::read(socket, asio::buffer(bytes, 2), error);
        if (error) break;
        std::uint64_t length = bytes[1] & 0x7F;
        const std::size_t extra = length == 126 ? 2 : length == 127 ? 8 : 0;
        if (extra > 0) {
          asio::read(socket, asio::buffer(bytes + 2, extra), error);
          length = 0;
          for (std::size_t i = 0; i < extra; ++i) length = (length << 8) | bytes[2 + i];
        }
        payload.resize(static_cast<std::size_t>(length));
        asio::read(socket, asio::buffer(payload), error);
        if ((bytes[0] & 0x0F) == 2) {
          last_frame_bytes = length;
          ++frames;
        }
      }
    });
  }
  ~Page() {
    stop = true;
    thread.join();
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::size_t particles = 100'000;
  double rate = 10.0;
  int pairs = 7;
  int blockSteps = 20;
  double serveSeconds = 0.0;
  CLI::App app("The live view's cost per step, A/B alternating (docs/view.md).", "demlink-bench-view");
  app.add_option("--particles", particles, "spheres in the bed");
  app.add_option("--rate", rate, "frames per second the page asks for");
  app.add_option("--pairs", pairs, "A/B block pairs");
  app.add_option("--block-steps", blockSteps, "steps per block");
  app.add_option("--serve", serveSeconds, "serve the bed unstepped for this many seconds instead [s]");
  if (const std::optional<int> exitCode = cli::parse(app, argc, argv)) return *exitCode;

  if (serveSeconds > 0.0) {
    const core::World still = bed(particles, false);
    server::LiveViewHub hub;
    server::ViewServer view(hub, {});
    view.start();
    std::printf("view: %s\n", view.url().c_str());
    std::fflush(stdout);
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(serveSeconds);
    while (std::chrono::steady_clock::now() < end) {
      hub.offer(still);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return 0;
  }

  core::World world = bed(particles);
  server::LiveViewHub hub;
  server::ViewServer view(hub, {});
  view.start();
  hub.offer(world);
  std::vector<double> a, b, ratios, offerShares;
  double offerSeconds = 0.0;
  std::uint64_t capturesInB = 0;
  {
    Page page(view.port(), rate);
    while (page.frames == 0) {  // the page is connected and has its first frame
      world.step();
      hub.offer(world);
    }
    for (int pair = 0; pair < pairs; ++pair) {
      double start = threadCpuSeconds();
      for (int k = 0; k < blockSteps; ++k) world.step();
      const double timeA = (threadCpuSeconds() - start) / blockSteps;
      double inOffer = 0.0;
      const std::uint64_t capturesBefore = hub.captures();
      start = threadCpuSeconds();
      for (int k = 0; k < blockSteps; ++k) {
        world.step();
        const double before = threadCpuSeconds();
        hub.offer(world);
        inOffer += threadCpuSeconds() - before;
      }
      const double timeB = (threadCpuSeconds() - start) / blockSteps;
      offerSeconds += inOffer;
      capturesInB += hub.captures() - capturesBefore;
      a.push_back(timeA);
      b.push_back(timeB);
      ratios.push_back(timeB / timeA);
      offerShares.push_back(inOffer / blockSteps / timeB);
    }
    std::printf("particles %zu, page asks %.0f frames/s; %llu captures, %llu frames received, %.2f bytes/particle/frame\n",
                particles, rate, static_cast<unsigned long long>(hub.captures()),
                static_cast<unsigned long long>(page.frames.load()),
                static_cast<double>(page.last_frame_bytes.load()) / static_cast<double>(particles));
  }
  std::printf("A (no view) %.3f ms/step, B (view) %.3f ms/step, B/A %.4f, median of pair ratios %.4f, "
              "offer() %.2f %% of B's step; %.3f ms per capture (%llu captures in B), i.e. %.2f %% of a second "
              "at %.0f frames/s\n",
              1e3 * median(a), 1e3 * median(b), median(b) / median(a), median(ratios), 100.0 * median(offerShares),
              1e3 * offerSeconds / static_cast<double>(std::max<std::uint64_t>(capturesInB, 1)),
              static_cast<unsigned long long>(capturesInB),
              100.0 * rate * offerSeconds / static_cast<double>(std::max<std::uint64_t>(capturesInB, 1)), rate);
  return 0;
}
