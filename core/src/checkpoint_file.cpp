/// The checkpoint file's header, the materials section and the file-level helpers
/// (format in checkpoint_file.hpp and docs/state.md). The world writes and reads the
/// sections in order (World::saveCheckpoint, world_checkpoint.cpp); each stateful
/// object writes and reads its own section payload, checking what it reads.
#include "demlink/core/checkpoint_file.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/input_file.hpp"
#include "demlink/core/state/state_stream.hpp"

namespace demlink::core {

namespace {


constexpr double kFloatProbe = -1.5;

}  // namespace

void writeCheckpointHeader(StateWriter& out) {
  out.writeBytes(kCheckpointMagic, 8);
  out.write(kCheckpointVersion);
  out.write(kCheckpointByteOrderMark);
  out.write(static_cast<std::uint32_t>(sizeof(double)));
  out.write(kFloatProbe);
}

/// Checks magic, version, byte order and float format; leaves `in` at the first section.
void readCheckpointHeader(StateReader& in) {
  char magic[8] = {};
  if (in.remaining() < sizeof magic) in.fail(std::to_string(in.remaining()) + " bytes", "too short for a checkpoint (empty or truncated file)");
  in.readBytes(magic, sizeof magic);
  if (std::string_view(magic, sizeof magic) != std::string_view(kCheckpointMagic, 8)) {
    in.fail("magic", "not a DEMLink checkpoint (the file does not start with \"DEMLCKPT\")");
  }
  const auto version = in.read<std::uint32_t>();
  if (version != kCheckpointVersion) {
    in.fail(std::to_string(version),
            "unsupported checkpoint format version (this engine reads version " +
                std::to_string(kCheckpointVersion) + ")");
  }
  const auto mark = in.read<std::uint32_t>();
  if (mark != kCheckpointByteOrderMark) in.fail("byte order", "written on a machine with another byte order");
  const auto doubleSize = in.read<std::uint32_t>();
  const auto probe = in.read<double>();
  if (doubleSize != sizeof(double) || probe != kFloatProbe) {
    in.fail("double format", "written with another floating-point format");
  }
}

namespace {

/// Skips sections until the one tagged `tag` and returns it.
StateReader findSection(StateReader& file, std::string_view tag, const std::string& name) {
  while (!file.atEnd() && file.peekTag() != tag) file.skipSection();
  return file.section(tag, name);
}

void writeMaterial(StateWriter& out, const Material& m) {
  out.writeString(m.name);
  for (double value : {m.density, m.youngs_modulus, m.poisson_ratio, m.restitution, m.sliding_friction,
                       m.rolling_friction}) {
    out.write(value);
  }
}

}  // namespace

void saveMaterials(StateWriter& out, const std::vector<Material>& materials) {
  out.write<std::uint64_t>(materials.size());
  for (const Material& m : materials) writeMaterial(out, m);
}

std::vector<std::string> readMaterialNames(StateReader in, std::vector<Material>* properties) {
  const auto count = in.read<std::uint64_t>();
  in.requireAvailable(count, sizeof(std::uint64_t) + 6 * sizeof(double), "material count");
  std::vector<std::string> names;
  for (std::uint64_t k = 0; k < count; ++k) {
    Material m;
    m.name = in.readString();
    m.density = in.read<double>();
    m.youngs_modulus = in.read<double>();
    m.poisson_ratio = in.read<double>();
    m.restitution = in.read<double>();
    m.sliding_friction = in.read<double>();
    m.rolling_friction = in.read<double>();
    names.push_back(m.name);
    if (properties) properties->push_back(m);
  }
  in.requireEnd();
  return names;
}

std::string checkpointFileName(std::uint64_t number) {
  char name[48];
  std::snprintf(name, sizeof name, "checkpoint_%06llu.bin", static_cast<unsigned long long>(number));
  return name;
}

std::string readCheckpointBytes(const std::filesystem::path& path) {
  return readInputFile("checkpoint file", path);
}

void writeCheckpointBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::filesystem::path temporary = path;
  temporary += ".partial";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write checkpoint " + temporary.string());
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) throw std::runtime_error("cannot write checkpoint " + temporary.string());
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) throw std::runtime_error("cannot rename " + temporary.string() + " to " + path.string() + ": " + ec.message());
}

CheckpointParticles readCheckpointParticles(const std::filesystem::path& path) {
  const std::string bytes = readCheckpointBytes(path);
  StateReader file(bytes, path.string(), "header");
  readCheckpointHeader(file);
  CheckpointParticles out;
  StateReader settings = findSection(file, "SETT", "settings");
  const double dt = settings.read<double>();
  out.material_names = readMaterialNames(findSection(file, "MATL", "materials"), nullptr);
  StateReader clock = findSection(file, "CLOK", "clock");
  out.time = static_cast<double>(clock.read<std::uint64_t>()) * dt;
  StateReader partSection = findSection(file, "PART", "particles");
  ParticleArrays p;
  p.restore(partSection);
  requireIndices(partSection, p.material, out.material_names.size(), "particle material index");
  out.particles.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    ParticleSpec& spec = out.particles[i];
    spec.position = p.position[i];
    spec.velocity = p.velocity[i];
    spec.angular_velocity = p.angular_velocity[i];
    spec.radius = p.radius[i];
    spec.material = p.material[i];
  }
  out.ids = p.id;
  return out;
}

}  // namespace demlink::core
