#pragma once
/// A scripted stand-in for demlink-server, for testing the client side without the real
/// server: it listens on 127.0.0.1 port 0, runs a script in its own thread, checks every
/// message it receives and answers with Welcome, Compiled, DataPackage, Finished or Error.
///
/// Why polling, non-blocking sockets: one script thread serves several connections (the
/// Modelica call sequence uses one connection per component, all from one thread), and
/// every wait has a deadline, so a client bug fails the test instead of hanging it.
/// A script reports a failed check by throwing; finish() returns the collected messages.
#include <asio.hpp>

#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "demlink/v1/protocol.pb.h"
#include "demlink/wire/frame_codec.hpp"

namespace demlink::testing {

using Clock = std::chrono::steady_clock;
inline constexpr std::chrono::milliseconds kStepTimeout{3000};

/// One accepted connection.
class FakePeer {
 public:
  explicit FakePeer(asio::ip::tcp::socket socket) : socket_(std::move(socket)) {
    socket_.non_blocking(true);
    socket_.set_option(asio::ip::tcp::no_delay(true));
  }

  /// A complete message if one has arrived (never blocks).
  std::optional<v1::ClientMessage> poll() {
    for (;;) {
      if (auto payload = decoder_.next()) {
        v1::ClientMessage message;
        if (!wire::parsePayload(*payload, message)) throw std::runtime_error("client sent a non-ClientMessage frame");
        return message;
      }
      if (closed_) return std::nullopt;
      std::array<char, 4096> buffer{};
      std::error_code ec;
      const std::size_t n = socket_.read_some(asio::buffer(buffer), ec);
      if (ec == asio::error::would_block || ec == asio::error::try_again) return std::nullopt;
      if (ec) {
        closed_ = true;
        return std::nullopt;
      }
      decoder_.feed(std::string_view(buffer.data(), n));
    }
  }

  /// The next message within the timeout; throws otherwise.
  v1::ClientMessage expect(const char* what, std::chrono::milliseconds timeout = kStepTimeout) {
    const auto deadline = Clock::now() + timeout;
    while (Clock::now() < deadline) {
      if (auto m = poll()) return *m;
      if (closed_) throw std::runtime_error(std::string("connection closed while waiting for ") + what);
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    throw std::runtime_error(std::string("timeout waiting for ") + what);
  }

  void send(const v1::ServerMessage& message) {
    const std::string frame = wire::encodeFrame(message);
    socket_.non_blocking(false);  // small frames: a blocking write completes at once
    std::error_code ec;
    asio::write(socket_, asio::buffer(frame), ec);
    socket_.non_blocking(true);
  }

  void sendError(v1::Error::Code code, const std::string& text, const std::string& component = "",
                 const std::string& field = "", bool fatal = true) {
    v1::ServerMessage m;
    auto* e = m.mutable_error();
    e->set_code(code);
    e->set_message(text);
    e->set_component(component);
    e->set_field(field);
    e->set_fatal(fatal);
    send(m);
  }

  void close() {
    std::error_code ec;
    socket_.shutdown(asio::ip::tcp::socket::shutdown_both, ec);
    socket_.close(ec);
    closed_ = true;
  }
  [[nodiscard]] bool closed() const { return closed_; }

 private:
  asio::ip::tcp::socket socket_;
  wire::FrameDecoder decoder_;
  bool closed_ = false;
};

class FakeServer {
 public:
  using Script = std::function<void(FakeServer&)>;

  FakeServer() : acceptor_(io_, asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0)) {
    acceptor_.non_blocking(true);
  }
  ~FakeServer() { (void)finish(); }
  FakeServer(const FakeServer&) = delete;
  FakeServer& operator=(const FakeServer&) = delete;

  [[nodiscard]] std::uint16_t port() const { return acceptor_.local_endpoint().port(); }

  void start(Script script) {
    thread_ = std::thread([this, s = std::move(script)] {
      try {
        s(*this);
      } catch (const std::exception& e) {
        std::lock_guard lock(mutex_);
        failure_ = e.what();
      }
      for (auto& p : peers_) p->close();  // the client sees EOF, never a hang
    });
  }

  /// Joins the script thread; the failure message, or "" when every check passed.
  std::string finish() {
    if (thread_.joinable()) thread_.join();
    std::lock_guard lock(mutex_);
    return failure_;
  }

  /// Accepts one connection within the timeout.
  FakePeer& accept(std::chrono::milliseconds timeout = kStepTimeout) {
    const auto deadline = Clock::now() + timeout;
    while (Clock::now() < deadline) {
      std::error_code ec;
      asio::ip::tcp::socket socket(io_);
      acceptor_.accept(socket, ec);
      if (!ec) {
        peers_.push_back(std::make_unique<FakePeer>(std::move(socket)));
        return *peers_.back();
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    throw std::runtime_error("timeout waiting for a connection");
  }

  /// Accepts a connection and answers its Hello with Welcome (checks the version).
  FakePeer& acceptHello(std::string* clientName = nullptr) {
    FakePeer& peer = accept();
    const auto hello = peer.expect("Hello");
    if (!hello.has_hello()) throw std::runtime_error("first message is not Hello");
    if (hello.hello().protocol_version() != v1::PROTOCOL_VERSION_CURRENT) throw std::runtime_error("wrong version");
    if (clientName != nullptr) *clientName = hello.hello().client_name();
    v1::ServerMessage welcome;
    welcome.mutable_welcome()->set_protocol_version(v1::PROTOCOL_VERSION_CURRENT);
    welcome.mutable_welcome()->set_server_name("fake-server");
    welcome.mutable_welcome()->set_simulation_number(1);
    peer.send(welcome);
    return peer;
  }

 private:
  asio::io_context io_;
  asio::ip::tcp::acceptor acceptor_;
  std::vector<std::unique_ptr<FakePeer>> peers_;
  std::thread thread_;
  std::mutex mutex_;
  std::string failure_;
};

/// Deterministic outputs the tests can check: every value encodes the step (and the
/// component id), so a client that shows the wrong interval's data is caught.
inline void fillFakeOutputs(const std::string& kind, std::uint32_t id, std::uint64_t step, v1::DataPackage& d,
                            const v1::RigidBodyInput* lastInput) {
  d.set_component_id(id);
  d.set_step(step);
  const double s = static_cast<double>(step);
  auto vec = [](v1::Vector3* v, double x, double y, double z) {
    v->set_x(x);
    v->set_y(y);
    v->set_z(z);
  };
  if (kind == "rigid_body") {
    auto* o = d.mutable_rigid_body();
    vec(o->mutable_mean_force(), s, 1.0, 2.0);
    vec(o->mutable_mean_torque(), 3.0, 4.0, 5.0);
    vec(o->mutable_force(), 6.0, 7.0, 8.0);
    vec(o->mutable_torque(), 9.0, 10.0, s + 0.5);
    if (lastInput != nullptr) {
      *o->mutable_position() = lastInput->position();
      *o->mutable_orientation() = lastInput->orientation();
    } else {
      o->mutable_orientation()->set_w(1.0);
    }
  } else if (kind == "region_sensor") {
    auto* o = d.mutable_region_sensor();
    o->set_count(step * 10 + id);
    o->set_mass(s * 0.25);
    if (step > 0) {  // at step 0 none, as the server sends an empty region's
      vec(o->mutable_centre_of_mass(), s, 0.0, 1.0);
      vec(o->mutable_mean_velocity(), 0.0, -s, 0.0);
    }
    o->set_bonds_intact(step * 100 + 7);
    o->set_bonds_broken(step * 100 + 3);
  } else if (kind == "simulation_box") {
    auto* o = d.mutable_simulation_box();
    o->set_time(s * 1e-3);
    o->set_particle_count(step * 2);
    o->set_total_mass(s);
    o->set_kinetic_energy(0.5 * s);
    o->set_step_rate(1000.0);
  } else if (kind == "particle_source" || kind == "particle_sink") {
    auto* o = kind == "particle_source" ? d.mutable_particle_source() : d.mutable_particle_sink();
    o->mutable_interval()->set_count(3);
    o->mutable_interval()->set_mass(0.3);
    o->mutable_total()->set_count(step * 3);
    o->mutable_total()->set_mass(s * 0.3);
    o->mutable_shortfall_total()->set_count(kind == "particle_source" ? 1 : 0);
  } else if (kind == "flow_sensor") {
    auto* o = d.mutable_flow_sensor();
    o->mutable_positive_interval()->set_count(1);
    o->mutable_negative_interval()->set_count(2);
    o->mutable_positive_total()->set_count(step);
    o->mutable_negative_total()->set_count(2 * step);
    o->mutable_positive_total()->set_mass(s);
  } else if (kind == "particle_view") {
    auto* o = d.mutable_particle_view();
    o->set_total_count(2);
    o->set_stride(1);
    for (float v : {0.0F, 1.0F, 2.0F, 3.0F, 4.0F, static_cast<float>(step)}) o->add_positions(v);
    o->add_radii(0.5F);
    o->add_radii(0.25F);
    o->add_ids(1);
    o->add_ids(2);
  }
}

/// The kind name of a declaration (the `kind` oneof field name).
inline std::string kindOf(const v1::ComponentDeclaration& d) {
  const auto* oneof = v1::ComponentDeclaration::descriptor()->FindOneofByName("kind");
  const auto* field = d.GetReflection()->GetOneofFieldDescriptor(d, oneof);
  return field == nullptr ? std::string() : std::string(field->name());
}

/// A miniature scheduler with the real server's contract: accept `connections` clients,
/// collect `expectedComponents` declarations, compile (ids from 1, interval steps =
/// round(interval / time step)), then run the sample grid: at each step wait for exactly
/// the due components' packages (checking id, owner and step), advance to the next step
/// where any component is due and answer the components whose interval ends there.
/// A Bye is answered with Finished at once and drops that connection's components.
/// `log` receives "step:name" for every package received, in order.
struct MiniScheduler {
  int connections = 1;
  std::size_t expectedComponents = 1;
  double time_step = 1e-3;  // [s]
  std::vector<std::string>* log = nullptr;
  std::vector<v1::ComponentDeclaration>* declarations = nullptr;  ///< as received

  void operator()(FakeServer& server) const {
    struct Entry {
      v1::ComponentDeclaration declaration;
      std::string kind;
      std::uint32_t id = 0;
      std::uint64_t interval = 0;
      FakePeer* peer = nullptr;
      bool sent = false;
      v1::RigidBodyInput last_input;
      bool has_input = false;
    };
    std::vector<FakePeer*> peers;
    for (int i = 0; i < connections; ++i) peers.push_back(&server.acceptHello());
    std::vector<Entry> entries;
    std::set<FakePeer*> done;

    // Returns the next message of any live peer (round robin), within the step timeout.
    auto next = [&](const char* what) -> std::pair<FakePeer*, v1::ClientMessage> {
      const auto deadline = Clock::now() + kStepTimeout;
      while (Clock::now() < deadline) {
        for (FakePeer* p : peers) {
          if (done.count(p) != 0U) continue;
          if (auto m = p->poll()) return {p, *m};
          if (p->closed()) throw std::runtime_error(std::string("a client disconnected while waiting for ") + what);
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
      throw std::runtime_error(std::string("timeout waiting for ") + what);
    };
    auto finished = [](std::uint64_t step, const std::string& reason) {
      v1::ServerMessage m;
      m.mutable_finished()->set_step(step);
      m.mutable_finished()->set_reason(reason);
      return m;
    };

    while (entries.size() < expectedComponents) {
      auto [peer, m] = next("Declare");
      if (!m.has_declare()) throw std::runtime_error("expected Declare, got another message");
      Entry e;
      e.declaration = m.declare().component();
      e.kind = kindOf(e.declaration);
      e.id = static_cast<std::uint32_t>(entries.size() + 1);
      e.interval = static_cast<std::uint64_t>(std::llround(e.declaration.communication_interval() / time_step));
      e.peer = peer;
      if (e.kind == "simulation_box" && e.declaration.simulation_box().end_time() <= 0.0) {
        peer->sendError(v1::Error::INVALID_DECLARATION, "end_time must be > 0", e.declaration.name(),
                        "simulation_box.end_time");
        return;
      }
      if (declarations != nullptr) declarations->push_back(e.declaration);
      entries.push_back(e);
    }
    for (FakePeer* p : peers) {
      v1::ServerMessage m;
      auto* c = m.mutable_compiled();
      c->set_time_step(time_step);
      c->mutable_report()->set_text("fake compile report");
      for (const Entry& e : entries) {
        if (e.peer != p) continue;
        auto* cc = c->add_components();
        cc->set_name(e.declaration.name());
        cc->set_id(e.id);
        cc->set_kind(e.kind);
        cc->set_interval_steps(e.interval);
        cc->set_remote(true);
        fillFakeOutputs(e.kind, e.id, 0, *c->add_initial_outputs(), nullptr);
      }
      for (const Entry& e : entries) {  // every connection's, as the server lists them
        auto* cc = c->add_all_components();
        cc->set_name(e.declaration.name());
        cc->set_id(e.id);
        cc->set_kind(e.kind);
        cc->set_interval_steps(e.interval);
        cc->set_remote(true);
      }
      p->send(m);
    }

    std::uint64_t step = 0;
    for (;;) {
      auto live = [&](const Entry& e) { return e.interval > 0 && done.count(e.peer) == 0U; };
      auto dueMissing = [&] {
        for (const Entry& e : entries) {
          if (live(e) && step % e.interval == 0 && !e.sent) return true;
        }
        return false;
      };
      while (dueMissing()) {
        auto [peer, m] = next("DataPackage");
        if (m.has_bye()) {
          done.insert(peer);
          peer->send(finished(step, "client said Bye"));
          continue;
        }
        if (!m.has_data()) throw std::runtime_error("expected DataPackage or Bye");
        const auto& d = m.data();
        Entry* target = nullptr;
        for (Entry& e : entries) {
          if (e.id == d.component_id()) target = &e;
        }
        if (target == nullptr || target->peer != peer) {
          peer->sendError(v1::Error::UNKNOWN_COMPONENT, "no such component id on this connection", "",
                          "data.component_id");
          throw std::runtime_error("package for unknown component " + std::to_string(d.component_id()));
        }
        if (d.step() != step || step % target->interval != 0 || target->sent) {
          throw std::runtime_error("package for '" + target->declaration.name() + "' at step " +
                                   std::to_string(d.step()) + " while the server is at step " + std::to_string(step));
        }
        if (target->kind == "rigid_body") {
          if (!d.has_rigid_body_input()) throw std::runtime_error("rigid body package without rigid_body_input");
          const auto& q = d.rigid_body_input().orientation();
          const double norm = std::sqrt(q.w() * q.w() + q.x() * q.x() + q.y() * q.y() + q.z() * q.z());
          if (std::abs(norm - 1.0) > 1e-6) {
            peer->sendError(v1::Error::INVALID_INPUT, "orientation is not a unit quaternion",
                            target->declaration.name(), "data.rigid_body_input.orientation");
            throw std::runtime_error("non-unit quaternion");
          }
          target->last_input = d.rigid_body_input();
          target->has_input = true;
        }
        target->sent = true;
        if (log != nullptr) log->push_back(std::to_string(step) + ":" + target->declaration.name());
      }
      if (done.size() == peers.size()) return;
      std::uint64_t nextStep = 0;
      for (const Entry& e : entries) {
        if (!live(e)) continue;
        const std::uint64_t candidate = (step / e.interval + 1) * e.interval;
        if (nextStep == 0 || candidate < nextStep) nextStep = candidate;
      }
      if (nextStep == 0) return;  // nothing is exchanged
      step = nextStep;
      for (Entry& e : entries) {
        if (!live(e) || step % e.interval != 0) continue;
        v1::ServerMessage m;
        fillFakeOutputs(e.kind, e.id, step, *m.mutable_data(), e.has_input ? &e.last_input : nullptr);
        e.peer->send(m);
        e.sent = false;
      }
    }
  }
};

}  // namespace demlink::testing
