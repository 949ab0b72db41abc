#pragma once
/// Seed corpus generation shared by the fuzzers: with DEMLINK_FUZZ_WRITE_SEEDS=DIR in the
/// environment a fuzzer writes its seeds into DIR and exits (scripts/run_fuzz.sh does this
/// before fuzzing), so the seeds always match the current schema instead of being stale
/// binary files in the repository.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <google/protobuf/stubs/logging.h>

#include "demlink/v1/protocol.pb.h"
#include "demlink/wire/frame_codec.hpp"

namespace demlink::fuzz {

/// A small valid scene (box, material, floor, 8 particles) whose box expects 4 components.
inline constexpr const char* kSeedSceneJson = R"({"components": [
  {"name": "box", "communication_interval": 1e-4, "simulation_box": {"time_step": 1e-5, "end_time": 1e-3,
    "coupling": {"expected_count": 4}}},
  {"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}},
  {"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}},
  {"name": "spheres", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.006,
    "origin": {"x": 0.01, "y": 0.01, "z": 0.003}, "counts": {"nx": 2, "ny": 2, "nz": 2}}}
]})";

inline v1::ClientMessage helloMessage(const std::string& name) {
  v1::ClientMessage message;
  message.mutable_hello()->set_protocol_version(v1::PROTOCOL_VERSION_CURRENT);
  message.mutable_hello()->set_client_name(name);
  return message;
}

inline v1::ClientMessage dataMessage(std::uint32_t component, std::uint64_t step) {
  v1::ClientMessage message;
  message.mutable_data()->set_component_id(component);
  message.mutable_data()->set_step(step);
  return message;
}

inline v1::ClientMessage byeMessage() {
  v1::ClientMessage message;
  message.mutable_bye()->set_reason("seed");
  return message;
}

/// Protobuf logs every string field with invalid UTF-8 it refuses to parse; for a fuzzer that
/// is most inputs, and the log would drown libFuzzer's own output.
inline void silenceProtobufLog() { google::protobuf::SetLogHandler(nullptr); }

/// Writes each seed as DIR/seed_NNN and exits, when DEMLINK_FUZZ_WRITE_SEEDS is set.
inline void writeSeedsIfAsked(const std::vector<std::string>& seeds) {
  const char* directory = std::getenv("DEMLINK_FUZZ_WRITE_SEEDS");
  if (directory == nullptr || *directory == '\0') return;
  std::filesystem::create_directories(directory);
  for (std::size_t k = 0; k < seeds.size(); ++k) {
    const std::string name = "seed_" + std::to_string(1000 + k).substr(1);
    std::ofstream(std::filesystem::path(directory) / name, std::ios::binary) << seeds[k];
  }
  std::printf("wrote %zu seeds to %s\n", seeds.size(), directory);
  std::exit(0);
}

}  // namespace demlink::fuzz
