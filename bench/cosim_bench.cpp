/// demlink-bench-cosim: what the co-simulation coupling costs (its two target figures; plan in
/// bench/cosim_bench.md, how to run it in docs/benchmarks.md "Co-simulation").
///
///   demlink-bench-cosim roundtrip [--clients N] [--exchanges M] [--warmup W] [--kind body|sensor]
///                                 [--spin off,on,forced] [--runs K] [--pace-us P] [--server hub|host]
///   demlink-bench-cosim overhead [--particles P] [--interval S] [--duration S] [--pairs K]
///   demlink-bench-cosim            (both, with the defaults: well under two minutes)
///
/// roundtrip: the server runs in this process exactly as demlink-server wires it
/// (SimulationHub, whose simulation steps on its own thread, + TcpServer on 127.0.0.1,
/// port 0, its own thread; --server host: the CosimHost on the network thread, without
/// the hand-off between the two threads); the world is empty
/// (a SimulationBox and one material, no particles), every client is a thread with its
/// own connection and one component exchanged every step.
/// Each client times every Session::exchange() (package out -> answer in) with
/// steady_clock; the distribution over all clients after a warm-up is printed. With N > 1
/// clients a round trip includes waiting for the slowest of them, since the server only
/// advances when every due package is in. Without --clients it runs N = 1, 4 and 16, and
/// first a raw loopback ping-pong (same socket options, no protobuf, no host): the floor,
/// with both threads blocking in their reads and with both polling.
/// The spin-then-block variants (--spin, default off,on) alternate K times (--runs) for
/// each client count; each prints its distribution, the process's CPU time (server and
/// clients) per exchange and the spin statistics, after the load average and the gate's
/// count of free CPUs. --pace-us P: each client starts an exchange every P microseconds
/// (e.g. 1000: a client in real time at a 1 ms interval) instead of back to back, so the
/// CPU figure shows what spinning costs while waiting for a paced partner.
///
/// overhead: a bed of P spheres (particle_lattice on a floor) with one client RigidBody
/// (a box pushed through the bed, PREDICTED motion) exchanged at the interval, against the
/// SAME scene advanced in this thread for the same steps with core::CoupledMotion fed the
/// same poses (no network, no protobuf). Pairs alternate in-process / coupled; medians are
/// reported because the machine is shared. Overhead = (T_coupled - T_inproc) / T_coupled.
///
/// Why plain main and not Google Benchmark: the quantity is a distribution of single events
/// (round trips) or a pair of long runs, not a throughput loop.
#include <sys/resource.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>

#include "demlink/cli/command_line.hpp"
#include "demlink/client/connection.hpp"
#include "demlink/client/rigid_body.hpp"
#include "demlink/client/sensor_components.hpp"
#include "demlink/client/session.hpp"
#include "demlink/core/parallel/spin_history.hpp"
#include "demlink/core/parallel/spin_wait.hpp"
#include "demlink/core/walls/coupled_motion.hpp"
#include "demlink/core/world.hpp"
#include "demlink/server/cosim/cosim_host.hpp"
#include "demlink/server/cosim/simulation_hub.hpp"
#include "demlink/server/net/asio.hpp"
#include "demlink/server/net/tcp_server.hpp"
#include "demlink/server/scene/particle_csv.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/server/scene/scene_translator.hpp"

namespace {

namespace fs = std::filesystem;
namespace cli = demlink::cli;
namespace v1 = demlink::v1;
namespace client = demlink::client;
namespace server = demlink::server;
namespace core = demlink::core;
using Clock = std::chrono::steady_clock;

constexpr double kWallLimitSeconds = 90.0;  ///< a configuration that takes longer is aborted

/// A double for JSON text without loss (std::to_string prints 1e-7 as 0.000000).
std::string num(double value) {
  std::array<char, 32> text{};
  std::snprintf(text.data(), text.size(), "%.17g", value);
  return text.data();
}

double secondsOf(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

/// This process's CPU time, all threads (getrusage) [s].
double processCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1.0e-6 * static_cast<double>(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1.0e-9 * static_cast<double>(ts.tv_nsec);
}

// --- statistics ------------------------------------------------------------------------

struct Distribution {
  std::size_t n = 0;
  double median_us = 0.0, p90_us = 0.0, p99_us = 0.0, max_us = 0.0;
};

/// Order statistics of nanosecond samples (reorders the vector).
Distribution distributionOf(std::vector<std::int64_t>& ns) {
  Distribution d;
  d.n = ns.size();
  if (ns.empty()) return d;
  auto at = [&](double q) {
    const auto k = static_cast<std::size_t>(std::min<double>(q * static_cast<double>(ns.size()),
                                                             static_cast<double>(ns.size() - 1)));
    std::nth_element(ns.begin(), ns.begin() + static_cast<std::ptrdiff_t>(k), ns.end());
    return 1.0e-3 * static_cast<double>(ns[k]);
  };
  d.median_us = at(0.5);
  d.p90_us = at(0.9);
  d.p99_us = at(0.99);
  d.max_us = 1.0e-3 * static_cast<double>(*std::max_element(ns.begin(), ns.end()));
  return d;
}

double medianOf(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  if (n == 0) return 0.0;
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// --- the in-process server -------------------------------------------------------------

/// The host behind counters: time spent inside it for DataPackages and the
/// server thread's CPU time from the first package to the last answer.
class TimedHandler final : public server::SessionHandler {
 public:
  explicit TimedHandler(server::CosimHost& host) : inner_(host) {}

  std::vector<server::Outgoing> connected(server::ConnectionId id, const v1::Hello& hello,
                                          server::SteadyClock::time_point now) override {
    return inner_.connected(id, hello, now);
  }
  std::vector<server::Outgoing> received(server::ConnectionId from, const v1::ClientMessage& message,
                                         server::SteadyClock::time_point now) override {
    // Only the overhead part counts: the thread CPU clock is a system call (~1.5 us on a
    // paravirtualised VM), twice per package on the round trip's critical path.
    if (!record_ || !message.has_data()) return inner_.received(from, message, now);
    const double cpu = threadCpuSeconds();
    if (packages_ == 0) first_cpu_ = cpu;
    const Clock::time_point begin = Clock::now();
    std::vector<server::Outgoing> out = inner_.received(from, message, now);
    const Clock::duration inHost = Clock::now() - begin;
    host_seconds_ += secondsOf(inHost);
    host_ns_.push_back(std::chrono::duration_cast<std::chrono::nanoseconds>(inHost).count());
    ++packages_;
    last_cpu_ = threadCpuSeconds();
    host_cpu_ += last_cpu_ - cpu;
    return out;
  }
  std::vector<server::Outgoing> disconnected(server::ConnectionId id, const std::string& why,
                                             server::SteadyClock::time_point now) override {
    return inner_.disconnected(id, why, now);
  }
  std::vector<server::Outgoing> poll(server::SteadyClock::time_point now) override { return inner_.poll(now); }
  [[nodiscard]] std::optional<server::SteadyClock::time_point> nextDeadline() const override {
    return inner_.nextDeadline();
  }
  std::vector<server::Outgoing> shutdown(const std::string& reason, server::SteadyClock::time_point now) override {
    return inner_.shutdown(reason, now);
  }

  /// Count and time the packages, keeping the wall time in the host of every package
  /// (reserve `count`); only for one client with one component, where packages and
  /// exchanges correspond one to one. Off (the round trip): nothing is timed.
  void recordEach(std::size_t count) {
    record_ = true;
    host_ns_.reserve(count);
  }
  [[nodiscard]] const std::vector<std::int64_t>& hostNanoseconds() const { return host_ns_; }
  [[nodiscard]] std::uint64_t packages() const { return packages_; }
  [[nodiscard]] double hostSeconds() const { return host_seconds_; }  ///< inside the host, for packages [s]
  [[nodiscard]] double hostCpuSeconds() const { return host_cpu_; }  ///< the same in CPU time [s]
  [[nodiscard]] double busyCpuSeconds() const { return last_cpu_ - first_cpu_; }

 private:
  server::CosimHost& inner_;
  std::uint64_t packages_ = 0;
  double host_seconds_ = 0.0;
  double host_cpu_ = 0.0;
  bool record_ = false;
  std::vector<std::int64_t> host_ns_;
  double first_cpu_ = 0.0;
  double last_cpu_ = 0.0;
};

/// Who answers the network loop: the host itself on the loop's thread (the overhead's
/// timed handler), or the SimulationHub with the simulation on its own thread, as
/// demlink-server wires the native backend.
enum class ServerWiring { kHost, kHub };

/// demlink-server's wiring in a thread: serves one simulation, then run() returns.
class InProcessServer {
 public:
  InProcessServer(const v1::Scene& baseScene, const fs::path& outputRoot,
                  std::chrono::nanoseconds spinWait = core::defaultSpinBudget(),
                  ServerWiring wiring = ServerWiring::kHost)
      : host_(wiring == ServerWiring::kHost ? std::make_unique<server::CosimHost>(hostOptions(baseScene, outputRoot))
                                            : nullptr),
        timed_(host_ ? std::make_unique<TimedHandler>(*host_) : nullptr),
        hub_(host_ ? nullptr : std::make_unique<server::SimulationHub>(hostOptions(baseScene, outputRoot), hubOptions(spinWait))),
        server_(timed_ ? static_cast<server::SessionHandler&>(*timed_) : *hub_, netOptions(spinWait)) {
    thread_ = std::thread([this] {
      server_.run();
      done_ = true;
    });
  }
  ~InProcessServer() {
    if (!done_) server_.stop("benchmark ended");
    thread_.join();
  }
  InProcessServer(const InProcessServer&) = delete;
  InProcessServer& operator=(const InProcessServer&) = delete;

  [[nodiscard]] std::uint16_t port() const { return server_.port(); }
  /// The host wiring only.
  [[nodiscard]] const TimedHandler& handler() const { return *timed_; }
  /// Before any client connects (the server thread only touches the handler for packages).
  [[nodiscard]] TimedHandler& handler() { return *timed_; }
  /// Waits for run() to return (the simulation ended); false after `seconds`.
  bool waitDone(double seconds) {
    const Clock::time_point end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                     std::chrono::duration<double>(seconds));
    while (!done_) {
      if (Clock::now() > end) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
  }

 private:
  static server::CosimOptions hostOptions(const v1::Scene& baseScene, const fs::path& outputRoot) {
    server::CosimOptions options;
    options.base_scene = baseScene;
    options.output_root = outputRoot;
    options.quiet_period_s = 30.0;  // every scene here says expected_count
    options.client_timeout_s = 30.0;
    return options;
  }
  static server::SimulationHubOptions hubOptions(std::chrono::nanoseconds spinWait) {
    server::SimulationHubOptions options;
    options.max_total = 1;
    options.spin_wait = spinWait;
    return options;
  }
  server::TcpServerOptions netOptions(std::chrono::nanoseconds spinWait) {
    server::TcpServerOptions options;
    options.spin_wait = spinWait;
    options.listen_address = "127.0.0.1";
    options.port = 0;
    options.stop_when = [this] { return (host_ ? host_->simulationsFinished() : hub_->simulationsFinished()) >= 1; };
    return options;
  }

  std::unique_ptr<server::CosimHost> host_;
  std::unique_ptr<TimedHandler> timed_;
  std::unique_ptr<server::SimulationHub> hub_;
  server::TcpServer server_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

client::ConnectOptions connectOptions(const std::string& name) {
  client::ConnectOptions options;
  options.client_name = name;
  options.timeout = std::chrono::milliseconds(30000);
  return options;
}

fs::path scratchDirectory(const std::string& what) {
  const fs::path dir = fs::temp_directory_path() /
                       ("demlink_bench_cosim_" + what + "_" + std::to_string(static_cast<long long>(::getpid())));
  fs::create_directories(dir);
  return dir;
}

// --- raw loopback floor ----------------------------------------------------------------

/// Ping-pong of a 50-byte message between two threads over loopback TCP with TCP_NODELAY:
/// the kernel's share of a round trip on this machine. `polling`: both threads poll their
/// socket (non-blocking recv) instead of blocking in the read, the floor of a round trip
/// whose two parties are awake (no wake-ups).
Distribution loopbackFloor(std::size_t exchanges, std::size_t warmup, bool polling) {
  constexpr std::size_t kBytes = 50;
  asio::io_context io;
  asio::ip::tcp::acceptor acceptor(io, asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  const std::uint16_t port = acceptor.local_endpoint().port();
  const std::size_t total = exchanges + warmup;
  // Reads exactly kBytes; false when the peer is gone.
  auto readAll = [polling](asio::ip::tcp::socket& socket, std::array<char, kBytes>& data) {
    if (!polling) {
      asio::read(socket, asio::buffer(data));
      return true;
    }
    std::size_t got = 0;
    while (got < kBytes) {
      const ssize_t n = ::recv(socket.native_handle(), data.data() + got, kBytes - got, MSG_DONTWAIT);
      if (n > 0) {
        got += static_cast<std::size_t>(n);
      } else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
        return false;
      } else {
        core::cpuRelax();
      }
    }
    return true;
  };
  std::thread echo([&] {
    asio::ip::tcp::socket socket(io);
    acceptor.accept(socket);
    socket.set_option(asio::ip::tcp::no_delay(true));
    std::array<char, kBytes> buffer{};
    for (std::size_t k = 0; k < total; ++k) {
      if (!readAll(socket, buffer)) return;
      asio::write(socket, asio::buffer(buffer));
    }
  });
  asio::io_context clientIo;
  asio::ip::tcp::socket socket(clientIo);
  socket.connect(asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  socket.set_option(asio::ip::tcp::no_delay(true));
  std::array<char, kBytes> buffer{};
  std::vector<std::int64_t> ns;
  ns.reserve(exchanges);
  for (std::size_t k = 0; k < total; ++k) {
    const Clock::time_point t0 = Clock::now();
    asio::write(socket, asio::buffer(buffer));
    if (!readAll(socket, buffer)) break;
    const Clock::time_point t1 = Clock::now();
    if (k >= warmup) ns.push_back(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
  }
  echo.join();
  return distributionOf(ns);
}

// --- roundtrip -------------------------------------------------------------------------

struct RoundtripOptions {
  std::size_t clients = 0;  ///< 0: 1, 4 and 16
  std::size_t exchanges = 0;  ///< per client, after the warm-up; 0: by client count
  std::size_t warmup = 1000;
  bool sensor = false;  ///< RegionSensor instead of RigidBody
  /// Spin-then-block variants, alternated within each repetition: off (block at once),
  /// on (the default budget behind the free-CPU gate), forced (the budget, gate open).
  std::vector<std::string> spin = {"off", "on"};
  std::size_t runs = 1;  ///< repetitions of the alternation
  std::size_t pace_us = 0;  ///< one exchange per client every pace_us [us]; 0: back to back
  ServerWiring wiring = ServerWiring::kHub;  ///< as demlink-server runs the native backend
};

/// How one roundtrip configuration ran.
struct RoundtripRun {
  std::vector<std::int64_t> ns;  ///< per exchange, all clients, after warm-up
  double wall = 0.0;             ///< [s]
  double cpu = 0.0;              ///< process CPU time, server and clients [s]
  core::SpinStats spins;         ///< spin-then-block waits during the run
  core::SpinHistoryStats history;  ///< waits that blocked at once on their history
};

/// Empty world: one material, a SimulationBox with fixed bounds, no particles.
v1::Scene emptyWorld(std::size_t clients, double timeStep) {
  const std::string json = R"({"components": [
    {"name": "steel", "material": {"density": 7800, "youngs_modulus": 2e8}},
    {"name": "box", "simulation_box": {"time_step": )" + num(timeStep) + R"(, "end_time": 0,
      "bounds": {"lower": {"x": -10, "y": -10, "z": -10}, "upper": {"x": 10, "y": 10, "z": 10}},
      "output": {"final_checkpoint": false, "final_particles_csv": false},
      "coupling": {"expected_count": )" + std::to_string(clients + 2) + R"(}}}]})";
  return server::parseSceneJson(json, "cosim bench (empty world)");
}

/// Runs one configuration; returns the per-exchange times of all clients (after warm-up).
RoundtripRun runRoundtrip(std::size_t clients, std::size_t exchanges, std::size_t warmup, bool sensor,
                          const std::string& spin, std::chrono::microseconds pace, ServerWiring wiring) {
  constexpr double kTimeStep = 1.0e-4;  // [s]; one exchange = one (empty) step
  const fs::path out = scratchDirectory("roundtrip");
  std::vector<std::vector<std::int64_t>> perClient(clients);
  std::vector<std::string> failures(clients);
  const std::chrono::nanoseconds budget = spin == "off" ? std::chrono::nanoseconds::zero() : core::defaultSpinBudget();
  core::SpinGate& gate = core::SpinGate::instance();
  gate.setForced(spin == "forced");
  const core::SpinStats spinsBefore = gate.stats();
  const core::SpinHistoryStats historyBefore = core::SpinHistory::stats();
  const double cpuBefore = processCpuSeconds();
  const Clock::time_point begin = Clock::now();
  {
    InProcessServer srv(emptyWorld(clients, kTimeStep), out, budget, wiring);
    std::vector<std::thread> threads;
    for (std::size_t c = 0; c < clients; ++c) {
      threads.emplace_back([&, c] {
        try {
          client::Connection connection;
          client::ConnectOptions options = connectOptions("bench-" + std::to_string(c));
          options.spin_wait = std::chrono::duration_cast<std::chrono::microseconds>(budget);
          connection.connect("127.0.0.1", srv.port(), options);
          client::Session session(connection);
          client::RigidBody* body = nullptr;
          if (sensor) {
            auto& s = session.add<client::RegionSensor>("sensor_" + std::to_string(c));
            s.setBox({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0});
            s.setCommunicationInterval(kTimeStep);
          } else {
            body = &session.add<client::RigidBody>("body_" + std::to_string(c));
            const client::Vec3 at{static_cast<double>(c) * 0.5 - 4.0, 0.0, 0.0};
            body->setBox({0.2, 0.2, 0.2}).setMaterial("steel").setInitialPose(at);
            body->setCommunicationInterval(kTimeStep);
          }
          session.declare();
          session.waitCompiled();
          std::vector<std::int64_t>& ns = perClient[c];
          ns.reserve(exchanges);
          const client::Vec3 at{static_cast<double>(c) * 0.5 - 4.0, 0.0, 0.0};
          Clock::time_point due = Clock::now();
          for (std::size_t k = 0; k < exchanges + warmup; ++k) {
            if (pace.count() > 0) {
              due += pace;
              std::this_thread::sleep_until(due);
            }
            if (body != nullptr) {
              body->setPose(at, {});
              body->setVelocity({}, {});
            }
            const Clock::time_point t0 = Clock::now();
            if (!session.exchange()) throw std::runtime_error("the simulation ended early");
            const Clock::time_point t1 = Clock::now();
            if (k >= warmup) ns.push_back(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
          }
          session.finish("benchmark done");
        } catch (const std::exception& error) {
          failures[c] = error.what();
        }
      });
    }
    for (std::thread& t : threads) t.join();
    if (!srv.waitDone(kWallLimitSeconds)) failures.emplace_back("the server did not end the simulation");
  }
  RoundtripRun run;
  run.wall = secondsOf(Clock::now() - begin);
  run.cpu = processCpuSeconds() - cpuBefore;
  const core::SpinStats spinsAfter = gate.stats();
  run.spins = {spinsAfter.ready_spinning - spinsBefore.ready_spinning,
               spinsAfter.blocked_after_spin - spinsBefore.blocked_after_spin,
               spinsAfter.refused - spinsBefore.refused};
  const core::SpinHistoryStats historyAfter = core::SpinHistory::stats();
  run.history = {historyAfter.partner_asleep - historyBefore.partner_asleep, historyAfter.late - historyBefore.late};
  gate.setForced(false);
  std::error_code ignored;
  fs::remove_all(out, ignored);
  for (const std::string& f : failures) {
    if (!f.empty()) throw std::runtime_error("roundtrip with " + std::to_string(clients) + " clients: " + f);
  }
  for (const auto& ns : perClient) run.ns.insert(run.ns.end(), ns.begin(), ns.end());
  return run;
}

void printDistribution(const char* label, const Distribution& d) {
  std::printf("%-34s n=%-7zu median %8.1f us  p90 %8.1f us  p99 %8.1f us  max %9.1f us\n", label, d.n, d.median_us,
              d.p90_us, d.p99_us, d.max_us);
}

void roundtrip(const RoundtripOptions& o, bool withFloor) {
  std::printf("== roundtrip: empty world, %s per client, exchanged every step, loopback TCP, %s ==\n",
              o.sensor ? "one region_sensor" : "one rigid_body (12-triangle box)",
              o.wiring == ServerWiring::kHub ? "the simulation on its own thread (SimulationHub)"
                                             : "the host on the network thread");
  if (withFloor) {
    const std::size_t n = o.exchanges > 0 ? o.exchanges : 20000;
    printDistribution("raw loopback ping-pong (50 B)", loopbackFloor(n, o.warmup, false));
    printDistribution("  the same, both polling", loopbackFloor(n, o.warmup, true));
  }
  std::vector<std::size_t> counts = {1, 4, 16};
  if (o.clients > 0) counts = {o.clients};
  char load[64] = "unknown";
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fgets(load, sizeof load, f) == nullptr) std::snprintf(load, sizeof load, "unknown");
    std::fclose(f);
    load[std::strcspn(load, "\n")] = '\0';
  }
  std::printf("load average before: %s; spin budget %.0f us; free CPUs by the gate now: %d of %u (others busy %.2f)\n",
              load, 1e-3 * static_cast<double>(core::defaultSpinBudget().count()),
              core::SpinGate::instance().freeCpus(), core::usableCpus(), core::SpinGate::instance().othersBusy());
  for (const std::size_t clients : counts) {
    std::size_t exchanges = o.exchanges;
    if (exchanges == 0) exchanges = clients == 1 ? 100000 : 20000;
    // Variants alternate within each repetition, so a change of load hits all alike.
    std::vector<std::vector<std::int64_t>> samples(o.spin.size());
    std::vector<double> cpu(o.spin.size(), 0.0), wall(o.spin.size(), 0.0);
    std::vector<core::SpinStats> spins(o.spin.size());
    std::vector<core::SpinHistoryStats> history(o.spin.size());
    for (std::size_t r = 0; r < o.runs; ++r) {
      for (std::size_t v = 0; v < o.spin.size(); ++v) {
        RoundtripRun run = runRoundtrip(clients, exchanges, o.warmup, o.sensor, o.spin[v],
                                        std::chrono::microseconds(o.pace_us), o.wiring);
        samples[v].insert(samples[v].end(), run.ns.begin(), run.ns.end());
        cpu[v] += run.cpu;
        wall[v] += run.wall;
        spins[v].ready_spinning += run.spins.ready_spinning;
        spins[v].blocked_after_spin += run.spins.blocked_after_spin;
        spins[v].refused += run.spins.refused;
        history[v].partner_asleep += run.history.partner_asleep;
        history[v].late += run.history.late;
      }
    }
    const auto total = static_cast<double>(o.runs * clients * (exchanges + o.warmup));  // exchanges, all clients
    for (std::size_t v = 0; v < o.spin.size(); ++v) {
      const Distribution d = distributionOf(samples[v]);
      const std::string label = std::to_string(clients) + (clients == 1 ? " client" : " clients (incl. waiting)") +
                                ", spin " + o.spin[v];
      printDistribution(label.c_str(), d);
      // CPU of server and clients per client exchange; at a 1 ms interval in real time an
      // exchange per client is due every ms, so this per ms is the share of one core.
      std::printf("%-34s %zu x %zu exchanges per client after %zu warm-up, %.1f s wall; CPU %.1f us per exchange "
                  "(%.1f %% of a core at one exchange per ms); spins: %llu ready, %llu blocked, %llu refused; "
                  "blocked at once: %llu partner asleep, %llu late\n",
                  "", o.runs, exchanges, o.warmup, wall[v], 1e6 * cpu[v] / total, 100.0 * 1e3 * cpu[v] / total,
                  static_cast<unsigned long long>(spins[v].ready_spinning),
                  static_cast<unsigned long long>(spins[v].blocked_after_spin),
                  static_cast<unsigned long long>(spins[v].refused),
                  static_cast<unsigned long long>(history[v].partner_asleep),
                  static_cast<unsigned long long>(history[v].late));
    }
    std::fflush(stdout);
  }
}

// --- overhead --------------------------------------------------------------------------

struct OverheadOptions {
  std::size_t particles = 10000;
  double interval = 1.0e-3;  ///< [s]
  double duration = 0.25;    ///< simulated [s]
  double settle = 0.15;      ///< simulated settling of the lattice before the timed runs [s]
  std::size_t pairs = 5;
};

struct BedScene {
  v1::Scene scene;    ///< material, floor, lattice, box (without the rigid body: the client declares it)
  double time_step;   ///< [s]
  std::uint64_t interval_steps;
  std::uint64_t exchanges;
  std::string particles_json;  ///< the particle_system component of the settled bed
};

constexpr double kRadius = 0.005;    // [m]
constexpr double kSpacing = 0.0105;  // [m] lattice pitch: 0.5 mm gaps, the bed settles a little
const client::Vec3 kBodySize{0.04, 0.04, 0.08};  // [m]
constexpr double kBodySpeed = 0.5;               // [m/s] along +x

std::string latticeJson(std::size_t particles) {
  const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(particles) / 16.0)));
  const std::size_t layers = (particles + side * side - 1) / (side * side);
  return R"({"name": "bed", "particle_lattice": {"material": "glass", "radius": )" + num(kRadius) +
         R"(, "spacing": )" + num(kSpacing) + R"(, "origin": {"x": 0, "y": 0, "z": )" +
         num(kRadius) + R"(}, "counts": {"nx": )" + std::to_string(side) + R"(, "ny": )" +
         std::to_string(side) + R"(, "nz": )" + std::to_string(layers) + "}}}";
}

/// Side of the lattice in x and y [m].
double bedSide(std::size_t particles) {
  const auto side = std::ceil(std::sqrt(static_cast<double>(particles) / 16.0));
  return (side - 1.0) * kSpacing + 2.0 * kRadius;
}

/// `particles`: the lattice JSON or a particle_system reading the settled bed's CSV.
v1::Scene bedScene(const std::string& particles, double timeStep, std::uint32_t expected, bool withBody,
                   const std::string& bodyJson) {
  std::string json = R"({"components": [
    {"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}},
    {"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}},
    )" + particles + R"(,
    {"name": "box", "simulation_box": {"time_step": )" + num(timeStep) + R"(, "end_time": 0,
      "output": {"final_checkpoint": false, "final_particles_csv": false},
      "coupling": {"expected_count": )" + std::to_string(expected) + "}}}";
  if (withBody) json += ",\n" + bodyJson;
  return server::parseSceneJson(json + "]}", "cosim bench (bed)");
}

std::string settledJson(const fs::path& csv) {
  return R"({"name": "bed", "particle_system": {"csv_file": ")" + csv.string() + R"("}})";
}

client::Vec3 bodyStart(std::size_t particles) {
  return {-0.5 * kBodySize.x - kRadius - 0.002, 0.5 * bedSide(particles), 0.5 * kBodySize.z + 0.005};
}

/// The rigid body as a scene component (for the in-process run; the client declares the same).
std::string bodyJson(std::size_t particles, double interval) {
  const client::Vec3 p = bodyStart(particles);
  return R"({"name": "pusher", "communication_interval": )" + num(interval) +
         R"(, "rigid_body": {"box": {"size": {"x": )" + num(kBodySize.x) + R"(, "y": )" +
         num(kBodySize.y) + R"(, "z": )" + num(kBodySize.z) +
         R"(}}, "material": "glass", "motion": "PREDICTED", "position": {"x": )" + num(p.x) +
         R"(, "y": )" + num(p.y) + R"(, "z": )" + num(p.z) + "}}}";
}

/// The time step (largest <= the critical limit that divides the interval), then the
/// lattice settled in this thread for `settle` simulated seconds and written to a CSV that
/// both runs load, so the timed runs start from a bed in contact (not from a free fall).
BedScene makeBed(const OverheadOptions& o, const fs::path& scratch) {
  server::TranslatedScene probe = server::translateScene(
      bedScene(latticeJson(o.particles), 1.0e-7, 4, true, bodyJson(o.particles, o.interval)), fs::path("."),
      server::SceneUse::Cosim);
  probe.world.initialize();
  const double limit = probe.world.timeStepReport().limit;
  const auto perInterval = static_cast<std::uint64_t>(std::ceil(o.interval / limit * (1.0 + 1.0e-12)));
  BedScene bed;
  bed.time_step = o.interval / static_cast<double>(perInterval);
  bed.interval_steps = perInterval;
  bed.exchanges = static_cast<std::uint64_t>(std::llround(o.duration / o.interval));

  server::TranslatedScene settle = server::translateScene(bedScene(latticeJson(o.particles), bed.time_step, 3, false, ""),
                                                          fs::path("."), server::SceneUse::Cosim);
  settle.world.initialize();
  const auto settleSteps = static_cast<std::uint64_t>(std::llround(o.settle / bed.time_step));
  const Clock::time_point begin = Clock::now();
  for (std::uint64_t s = 0; s < settleSteps; ++s) settle.world.step();
  const double settleSeconds = secondsOf(Clock::now() - begin);
  const fs::path csv = scratch / "settled_bed.csv";
  server::writeParticleCsv(settle.world, csv);
  bed.scene = bedScene(settledJson(csv), bed.time_step, 5, false, "");
  bed.particles_json = settledJson(csv);
  std::printf("bed: %zu spheres r = %.1f mm, critical step %.3g s -> dt %.4g s, %llu steps per exchange, "
              "%llu exchanges; settled %.3g s (%llu steps, %.1f ms per step)\n",
              settle.world.particles().size(), kRadius * 1e3, limit, bed.time_step,
              static_cast<unsigned long long>(perInterval), static_cast<unsigned long long>(bed.exchanges), o.settle,
              static_cast<unsigned long long>(settleSteps), 1e3 * settleSeconds / static_cast<double>(settleSteps));
  return bed;
}

core::RigidPose poseAt(const client::Vec3& start, double t) {
  core::RigidPose p;
  p.position = core::Vec3(start.x + kBodySpeed * t, start.y, start.z);
  return p;
}

struct InProcessResult {
  double seconds = 0.0;  ///< wall [s]
  double cpu = 0.0;      ///< this thread's CPU [s]
};

/// The same scene, the same poses, stepped in this thread: the physics alone.
InProcessResult runInProcess(const OverheadOptions& o, const BedScene& bed) {
  v1::Scene scene = bedScene(bed.particles_json, bed.time_step, 4, true, bodyJson(o.particles, o.interval));
  server::TranslatedScene t = server::translateScene(scene, fs::path("."), server::SceneUse::Cosim);
  core::World& world = t.world;
  world.initialize();
  std::size_t mesh = world.meshes().size();
  for (std::size_t m = 0; m < world.meshes().size(); ++m) {
    if (world.meshes()[m].name() == "pusher") mesh = m;
  }
  if (mesh == world.meshes().size()) throw std::runtime_error("in-process scene: no mesh named pusher");
  core::CoupledMotion motion(mesh, core::MotionMode::Predicted);
  const client::Vec3 start = bodyStart(o.particles);
  core::RigidTwist twist;
  twist.linear = core::Vec3(kBodySpeed, 0.0, 0.0);
  double checksum = 0.0;
  const double cpuBegin = threadCpuSeconds();
  const Clock::time_point begin = Clock::now();
  for (std::uint64_t k = 0; k < bed.exchanges; ++k) {
    const double t0 = static_cast<double>(k * bed.interval_steps) * bed.time_step;
    core::MeshBody& body = world.mesh(motion.meshIndex());
    const double dt = world.settings().time_step;
    motion.beginInterval(body, dt, poseAt(start, t0), twist, bed.interval_steps);
    for (std::uint64_t s = 0; s < bed.interval_steps; ++s) {
      world.step();
      motion.afterStep(body, dt);
    }
    checksum += motion.endInterval(body, dt).mean_force.x();
  }
  InProcessResult r;
  r.seconds = secondsOf(Clock::now() - begin);
  r.cpu = threadCpuSeconds() - cpuBegin;
  std::printf("  in-process: %8.3f s wall, %.3f s CPU  (mean force x summed %.4g N)\n", r.seconds, r.cpu, checksum);
  return r;
}

struct CoupledResult {
  double seconds = 0.0;       ///< client: first exchange to last answer [s]
  double host_seconds = 0.0;  ///< inside CosimHost for packages (stepping included) [s]
  double host_cpu = 0.0;      ///< the same in server thread CPU [s]
  double busy_cpu = 0.0;      ///< server thread CPU from the first package to the last [s]
  double client_cpu = 0.0;    ///< client thread CPU over its loop [s]
  /// Per exchange: client round trip minus the host's wall time for that package [ns].
  std::vector<std::int64_t> outside_ns;
  std::vector<std::int64_t> exchange_ns;  ///< per exchange: the client's round trip [ns]
};

CoupledResult runCoupled(const OverheadOptions& o, const BedScene& bed) {
  const fs::path out = scratchDirectory("overhead");
  CoupledResult r;
  double checksum = 0.0;
  {
    InProcessServer srv(bed.scene, out);
    srv.handler().recordEach(bed.exchanges + 1);
    client::Connection connection;
    connection.connect("127.0.0.1", srv.port(), connectOptions("bench-overhead"));
    client::Session session(connection);
    const client::Vec3 start = bodyStart(o.particles);
    auto& body = session.add<client::RigidBody>("pusher");
    body.setBox(kBodySize).setMaterial("glass").setInitialPose(start).setMotion(v1::RigidBody::PREDICTED);
    body.setCommunicationInterval(o.interval);
    session.declare();
    session.waitCompiled();
    if (session.timeStep() != bed.time_step || body.intervalSteps() != bed.interval_steps) {
      throw std::runtime_error("coupled scene compiled to another time step or interval");
    }
    const double cpuBegin = threadCpuSeconds();
    const Clock::time_point begin = Clock::now();
    for (std::uint64_t k = 0; k < bed.exchanges; ++k) {
      const double t0 = static_cast<double>(k * bed.interval_steps) * bed.time_step;
      body.setPose({start.x + kBodySpeed * t0, start.y, start.z}, {});
      body.setVelocity({kBodySpeed, 0.0, 0.0}, {});
      const Clock::time_point t0Exchange = Clock::now();
      if (!session.exchange()) throw std::runtime_error("the simulation ended early");
      r.exchange_ns.push_back(std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0Exchange).count());
      checksum += body.meanForce().x;
    }
    r.seconds = secondsOf(Clock::now() - begin);
    r.client_cpu = threadCpuSeconds() - cpuBegin;
    session.finish("benchmark done");
    if (!srv.waitDone(kWallLimitSeconds)) throw std::runtime_error("the server did not end the simulation");
    r.host_seconds = srv.handler().hostSeconds();
    r.host_cpu = srv.handler().hostCpuSeconds();
    const std::vector<std::int64_t>& inHost = srv.handler().hostNanoseconds();
    if (inHost.size() < r.exchange_ns.size()) throw std::runtime_error("fewer packages than exchanges");
    for (std::size_t k = 0; k < r.exchange_ns.size(); ++k) r.outside_ns.push_back(r.exchange_ns[k] - inHost[k]);
    r.busy_cpu = srv.handler().busyCpuSeconds();
  }
  std::error_code ignored;
  fs::remove_all(out, ignored);
  std::printf("  coupled:    %8.3f s wall, %.3f s CPU  (mean force x summed %.4g N; server thread %.3f s CPU, "
              "of which %.3f s in the host (%.3f s wall); client thread %.3f s CPU)\n",
              r.seconds, r.busy_cpu + r.client_cpu, checksum, r.busy_cpu, r.host_cpu, r.host_seconds, r.client_cpu);
  return r;
}

void overhead(const OverheadOptions& o) {
  std::printf("== overhead: %zu-sphere bed, one rigid_body at %.4g s interval, %.4g s simulated ==\n", o.particles,
              o.interval, o.duration);
  const fs::path scratch = scratchDirectory("bed");
  const BedScene bed = makeBed(o, scratch);
  std::vector<std::int64_t> outsideAll, exchangeAll;
  std::vector<double> inproc, inprocCpu, coupled, coupledCpu, host, busy, outside, ratio, ratioCpu;
  for (std::size_t pair = 0; pair < o.pairs; ++pair) {
    std::printf("pair %zu\n", pair + 1);
    const InProcessResult a = runInProcess(o, bed);
    const CoupledResult b = runCoupled(o, bed);
    inproc.push_back(a.seconds);
    inprocCpu.push_back(a.cpu);
    coupled.push_back(b.seconds);
    coupledCpu.push_back(b.busy_cpu + b.client_cpu);
    host.push_back(b.host_cpu);
    outside.push_back(b.busy_cpu - b.host_cpu);
    outsideAll.insert(outsideAll.end(), b.outside_ns.begin(), b.outside_ns.end());
    exchangeAll.insert(exchangeAll.end(), b.exchange_ns.begin(), b.exchange_ns.end());
    busy.push_back(b.busy_cpu);
    ratio.push_back((b.seconds - a.seconds) / b.seconds);
    ratioCpu.push_back((coupledCpu.back() - a.cpu) / coupledCpu.back());
    std::printf("  overhead this pair: wall %+.2f %%, CPU %+.2f %%\n", 100.0 * ratio.back(), 100.0 * ratioCpu.back());
    std::fflush(stdout);
  }
  const double a = medianOf(inproc);
  const double b = medianOf(coupled);
  const double ac = medianOf(inprocCpu);
  const double bc = medianOf(coupledCpu);
  const auto k = static_cast<double>(bed.exchanges);
  std::printf("wall: median in-process %.3f s, coupled %.3f s -> overhead %.2f %% (median of per-pair %.2f %%)\n", a,
              b, 100.0 * (b - a) / b, 100.0 * medianOf(ratio));
  std::printf("CPU:  median in-process %.3f s, coupled (server + client threads) %.3f s -> overhead %.2f %% "
              "(median of per-pair %.2f %%)\n",
              ac, bc, 100.0 * (bc - ac) / bc, 100.0 * medianOf(ratioCpu));
  std::printf("per exchange (%.0f): CPU coupled - in-process %.1f us; server thread outside the host %.1f us; "
              "wall coupled - in-process %.1f us\n",
              k, 1e6 * (bc - ac) / k, 1e6 * medianOf(outside) / k, 1e6 * (b - a) / k);
  const Distribution whole = distributionOf(exchangeAll);
  const Distribution extra = distributionOf(outsideAll);
  printDistribution("client exchange (all pairs)", whole);
  printDistribution("  of which outside the host", extra);
  std::printf("direct estimate: median outside-the-host time / median exchange = %.2f %%\n",
              100.0 * extra.median_us / whole.median_us);
  std::error_code ignored;
  fs::remove_all(scratch, ignored);
}

// --- command line ----------------------------------------------------------------------

/// Parses the command line (demlink/cli/command_line.hpp); an exit code when the program
/// should stop now (--help, --version: 0; bad input: 2).
std::optional<int> parse(int argc, char** argv, std::string& mode, RoundtripOptions& rt, OverheadOptions& ov) {
  CLI::App app("Co-simulation round trip and coupling overhead. No mode: roundtrip, then overhead.",
               "demlink-bench-cosim");
  app.add_option("mode", mode, "roundtrip, overhead or all (default all)")
      ->check(CLI::IsMember({"all", "roundtrip", "overhead"}));
  constexpr std::size_t kMany = 1'000'000'000;
  cli::addWholeNumber<std::size_t>(app, "--clients", rt.clients, 1, kMany, "roundtrip: clients (default: 1, 4, 16)");
  cli::addWholeNumber<std::size_t>(app, "--exchanges", rt.exchanges, 1, kMany, "roundtrip: exchanges per client");
  cli::addWholeNumber<std::size_t>(app, "--warmup", rt.warmup, 0, kMany, "roundtrip: warm-up exchanges (default 1000)");
  cli::addValue(app, "--kind", "roundtrip: body or sensor (default body)", [&rt](const std::string& text) {
    if (text != "body" && text != "sensor") cli::refuse("--kind", text, "expected body or sensor");
    rt.sensor = text == "sensor";
  });
  cli::addValue(app, "--spin", "roundtrip: spin variants to alternate, comma-separated, of off, on, forced "
                "(default off,on)", [&rt](const std::string& text) {
    rt.spin.clear();
    std::size_t begin = 0;
    while (begin <= text.size()) {
      const std::size_t end = std::min(text.find(',', begin), text.size());
      const std::string item = text.substr(begin, end - begin);
      if (item != "off" && item != "on" && item != "forced") cli::refuse("--spin", text, "expected off, on or forced");
      rt.spin.push_back(item);
      begin = end + 1;
    }
  });
  cli::addValue(app, "--server", "roundtrip: hub (the simulation on its own thread, as demlink-server runs it; "
                "default) or host (the host on the network thread)", [&rt](const std::string& text) {
    if (text != "hub" && text != "host") cli::refuse("--server", text, "expected hub or host");
    rt.wiring = text == "hub" ? ServerWiring::kHub : ServerWiring::kHost;
  });
  cli::addWholeNumber<std::size_t>(app, "--runs", rt.runs, 1, 1000, "roundtrip: repetitions of the alternation (default 1)");
  cli::addWholeNumber<std::size_t>(app, "--pace-us", rt.pace_us, 0, 1'000'000,
                                   "roundtrip: one exchange per client every P us (default 0: back to back)");
  cli::addWholeNumber<std::size_t>(app, "--particles", ov.particles, 1, kMany, "overhead: particles (default 10000)");
  cli::addNumber(app, "--interval", ov.interval, {0.0, true}, "overhead: communication interval [s] (default 0.001)");
  cli::addNumber(app, "--duration", ov.duration, {0.0, true}, "overhead: simulated time per run [s] (default 0.25)");
  cli::addNumber(app, "--settle", ov.settle, {0.0, true},
                 "overhead: simulated settling of the bed before the timed runs [s] (default 0.15)");
  cli::addWholeNumber<std::size_t>(app, "--pairs", ov.pairs, 1, kMany, "overhead: timed pairs (default 5)");
  return cli::parse(app, argc, argv);
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);  // the host logs joins and compiles at info
  std::string mode = "all";
  RoundtripOptions rt;
  OverheadOptions ov;
  if (const std::optional<int> exitCode = parse(argc, argv, mode, rt, ov)) return *exitCode;
  try {
    std::printf("demlink-bench-cosim: %u hardware threads\n", std::thread::hardware_concurrency());
    if (mode == "all" || mode == "roundtrip") roundtrip(rt, rt.clients == 0);
    if (mode == "all" || mode == "overhead") overhead(ov);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 1;
  }
  return 0;
}
