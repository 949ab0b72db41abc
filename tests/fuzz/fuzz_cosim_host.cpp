/// libFuzzer target: the CosimHost (compiler, scheduler, faults) fed arbitrary
/// ClientMessages from three fake connections, in process, with a fake clock.
///
/// Input: a sequence of [selector byte][frame]. selector % 3 picks the connection slot,
/// (selector / 3) % 8 the action: 0-4 deliver the following frame (as the transport would:
/// Hello first, then everything to received()), 5 disconnect the slot, 6 poll 1 s later,
/// 7 poll 60 s later (timeouts). Only "deliver" consumes a frame. The transport's rules are
/// mirrored, so whatever the host sees here it can see from the network. Checked: no crash
/// or sanitizer report, every Outgoing goes to a connection the host knows and has a message.
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>

#include "demlink/server/cosim/cosim_host.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "fuzz_seeds.hpp"

namespace {

using demlink::server::ConnectionId;
using demlink::server::Outgoing;
using demlink::server::SteadyClock;

void check(bool condition) {
  if (!condition) std::abort();
}

/// Bounds the work one input can ask for, so the fuzzer spends its time on the host's
/// logic rather than on legitimately long simulations (a 1e-220 s time step or a 1e6 s
/// interval is valid input that the server would dutifully step for ages; found by CI's
/// first fuzz runs as a libFuzzer timeout). Values that the compiler must refuse (NaN,
/// negative, zero) pass unchanged.
void boundWork(demlink::v1::ClientMessage& message) {
  if (!message.has_declare()) return;
  demlink::v1::ComponentDeclaration& c = *message.mutable_declare()->mutable_component();
  if (c.communication_interval() > 0.01) c.set_communication_interval(0.01);
  if (c.has_simulation_box()) {
    demlink::v1::SimulationBox& box = *c.mutable_simulation_box();
    if (box.has_time_step() && box.time_step() > 0.0 && box.time_step() < 1e-6) box.set_time_step(1e-6);
    if (box.end_time() > 0.01) box.set_end_time(0.01);
  }
  if (c.has_particle_lattice()) {
    demlink::v1::LatticeCounts& n = *c.mutable_particle_lattice()->mutable_counts();
    n.set_nx(std::min(n.nx(), 10u));
    n.set_ny(std::min(n.ny(), 10u));
    n.set_nz(std::min(n.nz(), 10u));
  }
  if (c.has_particle_source()) {
    demlink::v1::ParticleSource& source = *c.mutable_particle_source();
    if (source.rate_particles_per_s() > 1e4) source.set_rate_particles_per_s(1e4);
    if (source.rate_kg_per_s() > 10.0) source.set_rate_kg_per_s(10.0);
  }
}

class Session {
 public:
  explicit Session(demlink::server::CosimHost& host) : host_(host) {}

  void deliver(int slot, std::string_view payload) {
    demlink::v1::ClientMessage message;
    if (!demlink::wire::parsePayload(payload, message) ||
        message.message_case() == demlink::v1::ClientMessage::MESSAGE_NOT_SET) {
      disconnect(slot, "bad frame");
      return;
    }
    if (ids_[slot] == 0) {  // not past Hello: the transport refuses anything else
      if (!message.has_hello() || message.hello().protocol_version() != demlink::v1::PROTOCOL_VERSION_CURRENT) return;
      ids_[slot] = next_id_++;
      known_.insert(ids_[slot]);
      take(host_.connected(ids_[slot], message.hello(), now_));
      return;
    }
    boundWork(message);
    take(host_.received(ids_[slot], message, now_));
  }

  void disconnect(int slot, const std::string& why) {
    if (ids_[slot] == 0) return;
    const ConnectionId id = ids_[slot];
    ids_[slot] = 0;
    take(host_.disconnected(id, why, now_));
  }

  void poll(std::chrono::seconds later) {
    now_ += later;
    take(host_.poll(now_));
  }

  void end() { take(host_.shutdown("fuzz input ended", now_)); }
  void tick() { now_ += std::chrono::milliseconds(1); }

 private:
  void take(const std::vector<Outgoing>& messages) {
    std::vector<int> closing;
    for (const Outgoing& outgoing : messages) {
      check(known_.count(outgoing.to) == 1);
      check(outgoing.message.message_case() != demlink::v1::ServerMessage::MESSAGE_NOT_SET);
      check(outgoing.message.ByteSizeLong() < (std::size_t{1} << 30));
      if (!outgoing.close_after) continue;
      for (int slot = 0; slot < 3; ++slot) {
        if (ids_[slot] == outgoing.to) closing.push_back(slot);
      }
    }
    for (const int slot : closing) disconnect(slot, "closed after the host's message");  // the transport's contract
  }

  demlink::server::CosimHost& host_;
  ConnectionId ids_[3] = {0, 0, 0};
  ConnectionId next_id_ = 1;
  std::set<ConnectionId> known_;
  SteadyClock::time_point now_ = SteadyClock::time_point{} + std::chrono::hours(1);
};

std::filesystem::path outputRoot() {
  return std::filesystem::temp_directory_path() / ("demlink_fuzz_cosim_" + std::to_string(getpid()));
}

/// Selector byte for `action` on `slot`.
char selector(int action, int slot) { return static_cast<char>(action * 3 + slot); }

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  using namespace demlink;
  fuzz::silenceProtobufLog();
  spdlog::set_level(spdlog::level::off);  // the host logs every simulation; libFuzzer's output matters here
  const v1::Scene scene = server::parseSceneJson(fuzz::kSeedSceneJson, "seed scene");
  std::string declareAll;  // Hello and the four declarations on slot 0 (compiles on count)
  declareAll += selector(0, 0) + wire::encodeFrame(fuzz::helloMessage("seed"));
  for (const v1::ComponentDeclaration& component : scene.components()) {
    v1::ClientMessage declare;
    *declare.mutable_declare()->mutable_component() = component;
    declareAll += selector(0, 0) + wire::encodeFrame(declare);
  }
  std::string exchange = declareAll;
  // The box (id 1, the first declared) exchanges every 10 steps; the others are not exchanged.
  for (std::uint64_t step = 0; step <= 30; step += 10) {
    exchange += selector(0, 0) + wire::encodeFrame(fuzz::dataMessage(1, step));
  }
  std::string twoClients = declareAll;
  twoClients += selector(0, 1) + wire::encodeFrame(fuzz::helloMessage("second"));
  twoClients += selector(5, 0);  // first one drops mid-session
  twoClients += selector(7, 1);
  // Hostile but well-formed: long names and control bytes, extreme finite values, a path
  // on the server (this host has no data root: refused).
  std::string hostile = selector(0, 2) + wire::encodeFrame(fuzz::helloMessage(std::string(4000, 'h') + "\n\x1b[31m"));
  hostile += selector(0, 0) + wire::encodeFrame(fuzz::helloMessage("extreme"));
  for (const char* json :
       {R"({"name": "box", "communication_interval": 1e-4, "simulation_box": {"time_step": 1e-5, "end_time": 1e-3,
           "gravity": {"z": -1e308}, "frame": {"angular_velocity": {"z": 1e308}},
           "coupling": {"expected_count": 4, "client_timeout": 1e308}}})",
        R"({"name": "glass\n[00:00:00] error: forged", "material": {"youngs_modulus": 1.7976931348623157e308}})",
        R"({"name": "bucket", "communication_interval": 1e-4, "rigid_body": {"material": "glass",
           "stl_file": "/etc/passwd", "orientation": {"w": 1e308, "x": 1e308}}})",
        R"({"name": "spheres", "particle_lattice": {"material": "glass", "radius": 5e-324, "spacing": 1e308,
           "velocity": {"z": -1e308}, "counts": {"nx": 4294967295, "ny": 4294967295, "nz": 4294967295}}})"}) {
    v1::ClientMessage declare;
    *declare.mutable_declare()->mutable_component() = server::parseSceneJson(
        std::string(R"({"components": [)") + json + "]}", "hostile seed").components(0);
    hostile += selector(0, 0) + wire::encodeFrame(declare);
  }
  fuzz::writeSeedsIfAsked({exchange + selector(0, 0) + wire::encodeFrame(fuzz::byeMessage()),
                           declareAll + selector(7, 0), twoClients, hostile});
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  demlink::server::CosimOptions options;
  options.output_root = outputRoot();
  options.quiet_period_s = 0.5;
  options.client_timeout_s = 5.0;
  demlink::server::CosimHost host(options);
  Session session(host);
  // The decoder (with a small cap) cuts the frames exactly as the transport would.
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  std::size_t position = 0;
  while (position < bytes.size()) {
    const auto select = static_cast<std::uint8_t>(bytes[position++]);
    const int slot = select % 3;
    const int action = (select / 3) % 8;
    session.tick();
    if (action == 5) {
      session.disconnect(slot, "client closed the connection");
    } else if (action == 6) {
      session.poll(std::chrono::seconds(1));
    } else if (action == 7) {
      session.poll(std::chrono::seconds(60));
    } else {
      demlink::wire::FrameDecoder decoder(1 << 16);
      decoder.feed(bytes.substr(position));
      const std::optional<std::string> payload = decoder.next();
      if (!payload) break;  // truncated or malformed: the transport would close; input ends
      position = bytes.size() - decoder.pendingBytes();
      session.deliver(slot, *payload);
    }
  }
  session.end();
  std::error_code ignored;
  std::filesystem::remove_all(options.output_root, ignored);
  return 0;
}
