#pragma once
/// A scripted SessionHandler and a server running it on its own thread, for transport tests.
///
/// Script: Welcome on connect (client_name "throw": throws instead); a DataPackage is echoed
/// back (for component kLargeAnswerComponent with a particle view of kLargeAnswerBytes added); a Declare of a component named "throw" throws; Bye gets Finished and close_after;
/// Hello with client_name "poll" schedules a poll 100 ms later, which sends Finished
/// {reason "poll"}; shutdown sends Finished{reason} to everyone connected. Every call is
/// recorded (the server thread writes, the test thread reads: hence the mutex).
#include <gtest/gtest.h>

#include <algorithm>
#include <future>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "demlink/server/net/session_handler.hpp"
#include "demlink/server/net/tcp_server.hpp"
#include "test_client.hpp"

namespace demlink::server::test {

/// A package for this component is answered with a large view (back-pressure tests).
inline constexpr std::uint32_t kLargeAnswerComponent = 999;
inline constexpr std::size_t kLargeAnswerBytes = 1u << 20;

class FakeSessionHandler final : public SessionHandler {
 public:
  std::vector<Outgoing> connected(ConnectionId id, const v1::Hello& hello, SteadyClock::time_point now) override {
    const std::lock_guard lock(mutex_);
    calls_.push_back("connected " + std::to_string(id));
    if (hello.client_name() == "throw") throw std::runtime_error("scripted failure in connected");
    if (hello.client_name() == "poll") {
      deadline_ = now + std::chrono::milliseconds(100);
      poll_client_ = id;
    }
    live_.insert(id);
    Outgoing out{id, {}, false};
    out.message.mutable_welcome()->set_protocol_version(v1::PROTOCOL_VERSION_CURRENT);
    out.message.mutable_welcome()->set_simulation_number(1);
    return {out};
  }

  std::vector<Outgoing> received(ConnectionId from, const v1::ClientMessage& message,
                                 SteadyClock::time_point /*now*/) override {
    const std::lock_guard lock(mutex_);
    calls_.push_back("received " + std::to_string(from));
    Outgoing out{from, {}, false};
    if (message.has_data()) {
      *out.message.mutable_data() = message.data();
      if (message.data().component_id() == kLargeAnswerComponent) {
        out.message.mutable_data()->mutable_particle_view()->mutable_positions()->Resize(kLargeAnswerBytes / 4, 1.0f);
      }
    } else if (message.has_declare() && message.declare().component().name() == "throw") {
      throw std::runtime_error("scripted failure in received");
    } else if (message.has_bye()) {
      out.message.mutable_finished()->set_reason("bye");
      out.close_after = true;
      ++byes_;
    } else {
      return {};
    }
    return {out};
  }

  std::vector<Outgoing> disconnected(ConnectionId id, const std::string& why, SteadyClock::time_point /*now*/) override {
    const std::lock_guard lock(mutex_);
    calls_.push_back("disconnected " + std::to_string(id) + ": " + why);
    live_.erase(id);
    return {};
  }

  std::vector<Outgoing> poll(SteadyClock::time_point now) override {
    const std::lock_guard lock(mutex_);
    calls_.push_back("poll");
    if (!deadline_ || now < *deadline_) return {};
    polled_late_enough_ = true;
    deadline_.reset();
    Outgoing out{poll_client_, {}, false};
    out.message.mutable_finished()->set_reason("poll");
    return {out};
  }

  [[nodiscard]] std::optional<SteadyClock::time_point> nextDeadline() const override {
    const std::lock_guard lock(mutex_);
    return deadline_;
  }

  std::vector<Outgoing> shutdown(const std::string& reason, SteadyClock::time_point /*now*/) override {
    const std::lock_guard lock(mutex_);
    calls_.push_back("shutdown " + reason);
    std::vector<Outgoing> out;
    for (const ConnectionId id : live_) {
      Outgoing message{id, {}, false};
      message.message.mutable_finished()->set_reason(reason);
      out.push_back(message);
    }
    return out;
  }

  std::vector<std::string> calls() const {
    const std::lock_guard lock(mutex_);
    return calls_;
  }
  /// Number of recorded calls starting with `prefix`.
  std::size_t count(const std::string& prefix) const {
    const std::lock_guard lock(mutex_);
    return static_cast<std::size_t>(
        std::count_if(calls_.begin(), calls_.end(), [&](const std::string& call) { return call.starts_with(prefix); }));
  }
  /// The first recorded call starting with `prefix`, waiting up to kTimeout for it.
  std::string waitForCall(const std::string& prefix) const {
    const TestClock::time_point deadline = TestClock::now() + kTimeout;
    while (TestClock::now() < deadline) {
      {
        const std::lock_guard lock(mutex_);
        for (const std::string& call : calls_) {
          if (call.starts_with(prefix)) return call;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return "(no call starting with \"" + prefix + "\")";
  }
  bool polledLateEnough() const {
    const std::lock_guard lock(mutex_);
    return polled_late_enough_;
  }
  int byes() const {
    const std::lock_guard lock(mutex_);
    return byes_;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> calls_;
  std::set<ConnectionId> live_;
  std::optional<SteadyClock::time_point> deadline_;
  ConnectionId poll_client_ = 0;
  bool polled_late_enough_ = false;
  int byes_ = 0;
};

/// A TcpServer on 127.0.0.1, port 0, serving on its own thread until stopped.
class RunningServer {
 public:
  /// `stopAfterBye`: options.stop_when becomes "the handler has seen a Bye" (--once).
  explicit RunningServer(TcpServerOptions options = {}, bool stopAfterBye = false)
      : server_(handler_, withTestDefaults(std::move(options), stopAfterBye ? &handler_ : nullptr)) {
    thread_ = std::thread([this] {
      server_.run();
      done_.set_value();
    });
  }
  ~RunningServer() {
    if (thread_.joinable()) stop("test end");
  }
  RunningServer(const RunningServer&) = delete;
  RunningServer& operator=(const RunningServer&) = delete;

  [[nodiscard]] std::uint16_t port() const { return server_.port(); }
  FakeSessionHandler& handler() { return handler_; }
  /// True if run() returned within the timeout; otherwise the io_context is forced to stop.
  bool waitForReturn(std::chrono::milliseconds timeout = kTimeout) {
    const bool returned = finished_.wait_for(timeout) == std::future_status::ready;
    if (!returned) server_.context().stop();
    thread_.join();
    return returned;
  }
  /// stop(reason), then waitForReturn().
  bool stop(const std::string& reason) {
    server_.stop(reason);
    return waitForReturn();
  }

 private:
  static TcpServerOptions withTestDefaults(TcpServerOptions options, const FakeSessionHandler* stopAfterBye) {
    options.listen_address = "127.0.0.1";
    options.port = 0;
    if (stopAfterBye != nullptr) options.stop_when = [stopAfterBye] { return stopAfterBye->byes() > 0; };
    return options;
  }

  FakeSessionHandler handler_;
  TcpServer server_;
  std::promise<void> done_;
  std::future<void> finished_ = done_.get_future();
  std::thread thread_;
};

/// The client receives a fatal Error with `code` (naming `field` when one is given), then
/// the server closes the connection.
inline void expectRefused(TestClient& client, v1::Error::Code code, const std::string& messagePart = "",
                          const std::string& field = "") {
  const std::optional<v1::ServerMessage> answer = client.receive(5000ms);
  ASSERT_TRUE(answer.has_value()) << "no answer";
  ASSERT_TRUE(answer->has_error()) << answer->DebugString();
  EXPECT_EQ(answer->error().code(), code) << answer->DebugString();
  if (!field.empty()) {
    EXPECT_EQ(answer->error().field(), field);
  }
  EXPECT_TRUE(answer->error().fatal());
  EXPECT_NE(answer->error().message().find(messagePart), std::string::npos) << answer->error().message();
  EXPECT_TRUE(client.waitForClose(5000ms)) << "the server must close the connection after a fatal error";
}

/// A new connection still completes Hello (the server survived).
inline void expectStillServing(const RunningServer& server) {
  TestClient client(server.port());
  const std::optional<v1::ServerMessage> welcome = client.hello();
  ASSERT_TRUE(welcome.has_value());
  EXPECT_TRUE(welcome->has_welcome()) << welcome->DebugString();
}

}  // namespace demlink::server::test
