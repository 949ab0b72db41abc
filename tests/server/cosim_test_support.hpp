#pragma once
/// Drives a CosimHost in-process for the co-simulation tests: builds Hello /
/// Declare / DataPackage / Bye messages, keeps a fake clock, and files every outgoing
/// message into a per-connection inbox, so a test reads like a client script.
#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "demlink/core/checkpoint_file.hpp"
#include "demlink/server/cosim/cosim_host.hpp"
#include "demlink/server/scene/proto_convert.hpp"
#include "scene_test_support.hpp"
#include "test_support.hpp"

namespace demlink::server::test {

/// One component declaration from its JSON object, e.g. {"name": "m", "material": {}}.
inline v1::ComponentDeclaration declarationOf(const std::string& json) { return sceneOf({json}).components(0); }

/// A simulation_box component; `extra` is spliced into the simulation_box object. Its
/// loose restitution tolerance keeps the steps these exchange tests were written for
/// inside the limit (they test the protocol, not restitution).
inline std::string boxJson(double timeStep, double endTime, const std::string& extra = "",
                           double communicationInterval = 0.0) {
  return R"({"name": "box", "communication_interval": )" + std::to_string(communicationInterval) +
         R"(, "simulation_box": {"time_step": )" + std::to_string(timeStep) + R"(, "end_time": )" +
         std::to_string(endTime) + R"(, "restitution_tolerance": 0.2, "output": {"final_particles_csv": true})" +
         (extra.empty() ? "" : ", " + extra) + "}}";
}

inline v1::RigidBodyInput bodyInput(const core::Vec3& position, const core::Quat& orientation,
                                    const core::Vec3& velocity = core::Vec3::Zero(),
                                    const core::Vec3& angular = core::Vec3::Zero()) {
  v1::RigidBodyInput in;
  setVec3(*in.mutable_position(), position);
  setQuat(*in.mutable_orientation(), orientation);
  setVec3(*in.mutable_linear_velocity(), velocity);
  setVec3(*in.mutable_angular_velocity(), angular);
  return in;
}

class CosimHarness {
 public:
  explicit CosimHarness(const std::filesystem::path& outputRoot, v1::Scene baseScene = {},
                        std::filesystem::path recordFile = {}, bool overwrite = false)
      : host_(options(outputRoot, std::move(baseScene), std::move(recordFile), overwrite)) {}
  /// A host with options of the test's own (options() as the starting point).
  explicit CosimHarness(CosimOptions hostOptions) : host_(std::move(hostOptions)) {}

  static CosimOptions options(const std::filesystem::path& outputRoot, v1::Scene baseScene,
                                     std::filesystem::path recordFile, bool overwrite = false) {
    CosimOptions o;
    o.overwrite = overwrite;
    o.base_scene = std::move(baseScene);
    o.output_root = outputRoot;
    o.quiet_period_s = 2.0;
    o.client_timeout_s = 30.0;
    o.assembly_timeout_s = 60.0;
    o.progress_interval_s = 0.0;  // progress lines are tested through demlink-server (tests/net)
    o.record_file = std::move(recordFile);
    return o;
  }

  CosimHost& host() { return host_; }
  SteadyClock::time_point now() const { return now_; }
  void advanceClock(double seconds) {
    now_ += std::chrono::duration_cast<SteadyClock::duration>(std::chrono::duration<double>(seconds));
  }

  void take(std::vector<Outgoing> messages) {
    for (Outgoing& m : messages) {
      if (m.close_after) closed_[m.to] = true;
      inbox_[m.to].push_back(std::move(m.message));
    }
  }

  void hello(ConnectionId id, const std::string& name = "client", const std::string& simulation = "") {
    v1::Hello h;
    h.set_protocol_version(1);
    h.set_client_name(name);
    h.set_simulation(simulation);
    take(host_.connected(id, h, now_));
  }
  void declare(ConnectionId id, const std::string& componentJson) { declare(id, declarationOf(componentJson)); }
  void declare(ConnectionId id, const v1::ComponentDeclaration& component) {
    v1::ClientMessage m;
    *m.mutable_declare()->mutable_component() = component;
    take(host_.received(id, m, now_));
  }
  void send(ConnectionId id, const v1::DataPackage& package) {
    v1::ClientMessage m;
    *m.mutable_data() = package;
    take(host_.received(id, m, now_));
  }
  /// A package without inputs (sensors, views, the box).
  void sample(ConnectionId id, std::uint32_t component, std::uint64_t step) {
    v1::DataPackage p;
    p.set_component_id(component);
    p.set_step(step);
    send(id, p);
  }
  void sampleBody(ConnectionId id, std::uint32_t component, std::uint64_t step, const v1::RigidBodyInput& input) {
    v1::DataPackage p;
    p.set_component_id(component);
    p.set_step(step);
    *p.mutable_rigid_body_input() = input;
    send(id, p);
  }
  void bye(ConnectionId id) {
    v1::ClientMessage m;
    m.mutable_bye()->set_reason("done");
    take(host_.received(id, m, now_));
  }
  void poll() { take(host_.poll(now_)); }

  [[nodiscard]] std::vector<v1::ServerMessage>& inbox(ConnectionId id) { return inbox_[id]; }
  [[nodiscard]] bool closed(ConnectionId id) const { return closed_.contains(id); }

  [[nodiscard]] std::optional<v1::Compiled> compiled(ConnectionId id) {
    for (const v1::ServerMessage& m : inbox_[id]) {
      if (m.has_compiled()) return m.compiled();
    }
    return std::nullopt;
  }
  [[nodiscard]] std::vector<v1::Error> errors(ConnectionId id) {
    std::vector<v1::Error> out;
    for (const v1::ServerMessage& m : inbox_[id]) {
      if (m.has_error()) out.push_back(m.error());
    }
    return out;
  }
  [[nodiscard]] std::optional<v1::Finished> finished(ConnectionId id) {
    for (const v1::ServerMessage& m : inbox_[id]) {
      if (m.has_finished()) return m.finished();
    }
    return std::nullopt;
  }
  /// Data packages received by `id` (in order).
  [[nodiscard]] std::vector<v1::DataPackage> data(ConnectionId id) {
    std::vector<v1::DataPackage> out;
    for (const v1::ServerMessage& m : inbox_[id]) {
      if (m.has_data()) out.push_back(m.data());
    }
    return out;
  }
  /// The last data package for `component` received by `id`.
  [[nodiscard]] std::optional<v1::DataPackage> lastData(ConnectionId id, std::uint32_t component) {
    std::optional<v1::DataPackage> out;
    for (const v1::ServerMessage& m : inbox_[id]) {
      if (m.has_data() && m.data().component_id() == component) out = m.data();
    }
    return out;
  }
  /// The id of component `name` from the Compiled message of `id` (0: not found).
  [[nodiscard]] std::uint32_t idOf(ConnectionId id, const std::string& name) {
    const std::optional<v1::Compiled> c = compiled(id);
    if (!c) return 0;
    for (const v1::CompiledComponent& k : c->all_components()) {
      if (k.name() == name) return k.id();
    }
    return 0;
  }
  void clearInbox(ConnectionId id) { inbox_[id].clear(); }

 private:
  CosimHost host_;
  SteadyClock::time_point now_{};
  std::map<ConnectionId, std::vector<v1::ServerMessage>> inbox_;
  std::map<ConnectionId, bool> closed_;
};

/// Material, floor and a small lattice of spheres resting at z ~ radius (JSON components).
inline std::vector<std::string> smallBedJson(std::uint32_t n = 3) {
  return {R"({"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}})",
          R"({"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}})",
          R"({"name": "bed", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.0042,
              "origin": {"x": 0.0, "y": 0.0, "z": 0.002}, "counts": {"nx": )" +
              std::to_string(n) + R"(, "ny": )" + std::to_string(n) + R"(, "nz": 1}}})"};
}

inline std::string fileBytes(const std::filesystem::path& path) { return readText(path); }

/// Runs connection `id`'s compiled simulation to its end: sends the box's step-0 package,
/// then answers every package with the next (at most 100 rounds).
inline void runToTheEnd(CosimHarness& h, ConnectionId id) {
  h.sample(id, h.idOf(id, "box"), 0);
  std::size_t read = 0;
  for (int guard = 0; guard < 100 && !h.finished(id); ++guard) {
    while (read < h.inbox(id).size()) {
      const v1::ServerMessage m = h.inbox(id)[read++];
      if (m.has_data() && !h.finished(id)) h.sample(id, m.data().component_id(), m.data().step());
    }
  }
}

}  // namespace demlink::server::test
