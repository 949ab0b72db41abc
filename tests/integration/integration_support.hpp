#pragma once
/// Pieces the end-to-end tests share: the real co-simulation server (CosimHost
/// behind a TcpServer on an ephemeral loopback port) running on its own thread inside the
/// test process, client components built from plain JSON declarations, and a reader of the
/// host's session record.
///
/// Why in-process: the tests then see the host's output directory and can compare it with
/// an engine-only run, while the clients still talk to it over real sockets exactly as
/// remote system models would. The server thread is always stopped and joined by the
/// destructor, so a failing test never leaves a server behind.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "demlink/client/client.hpp"
#include "demlink/server/cosim/cosim_host.hpp"
#include "demlink/server/net/tcp_server.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/v1/recording.pb.h"
#include "demlink/wire/frame_codec.hpp"

namespace demlink::integration {

/// Bound of every blocking client call [ms]: far above any interval's simulation time, far
/// below the ctest timeout, so a protocol bug fails the test instead of hanging it.
inline constexpr std::chrono::milliseconds kClientTimeout{10000};

/// CosimHost + TcpServer on 127.0.0.1, port 0, served by one thread.
class InProcessServer {
 public:
  explicit InProcessServer(server::CosimOptions options)
      : host_(std::move(options)), tcp_(host_, server::TcpServerOptions{}) {
    thread_ = std::thread([this] { tcp_.run(); });
  }
  ~InProcessServer() { stop(); }
  InProcessServer(const InProcessServer&) = delete;
  InProcessServer& operator=(const InProcessServer&) = delete;

  [[nodiscard]] std::uint16_t port() const { return tcp_.port(); }
  /// Stops serving and joins the thread; the host may be inspected afterwards.
  void stop() {
    if (!thread_.joinable()) return;
    tcp_.stop("test over");
    thread_.join();
  }
  /// Only after stop(): the host is not thread-safe while the server thread runs.
  [[nodiscard]] server::CosimHost& host() { return host_; }

 private:
  server::CosimHost host_;
  server::TcpServer tcp_;
  std::thread thread_;
};

/// Host options for a test: output under `root`, short quiet period.
inline server::CosimOptions hostOptions(const std::filesystem::path& root) {
  server::CosimOptions o;
  o.output_root = root;
  o.quiet_period_s = 0.5;
  o.client_timeout_s = 10.0;
  return o;
}

/// A client component given by a whole declaration (kinds the client library has no class
/// for, e.g. particle_lattice, or a declaration written as JSON).
class Declared : public client::Component {
 public:
  explicit Declared(const v1::ComponentDeclaration& declaration) : client::Component(declaration.name()) {
    this->declaration() = declaration;
  }
};

/// One component declaration from its JSON object.
inline v1::ComponentDeclaration declarationOf(const std::string& json) {
  return server::parseSceneJson("{\"components\": [" + json + "]}", "integration test").components(0);
}

/// A connected connection with the test's timeout.
inline void connect(client::Connection& connection, std::uint16_t port, const std::string& name) {
  client::ConnectOptions options;
  options.client_name = name;
  options.timeout = kClientTimeout;
  connection.connect("127.0.0.1", port, options);
}

inline std::string fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

/// The events of a session record (the host's record_file), in order.
inline std::vector<v1::SessionEvent> readRecord(const std::filesystem::path& path) {
  wire::FrameDecoder decoder;
  decoder.feed(fileBytes(path));
  std::vector<v1::SessionEvent> events;
  while (std::optional<std::string> payload = decoder.next()) {
    v1::SessionEvent event;
    if (!wire::parsePayload(*payload, event)) break;
    events.push_back(std::move(event));
  }
  return events;
}

}  // namespace demlink::integration
