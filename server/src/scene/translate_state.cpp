/// ParticleSystem translation: a saved particle set (CSV or checkpoint) becomes
/// world particles.
///
/// Why the world assigns new ids: ids are the world's stable handles, handed out
/// in declaration order; a loaded set may come from a run whose ids collide with
/// particles declared earlier in this scene. The file's order is kept, so the new
/// ids follow the old ones' order, and the CSV's ids are still checked for
/// uniqueness (a repeated id means a corrupt or concatenated file).
#include "demlink/server/scene/translate_state.hpp"

#include <vector>

#include "demlink/core/checkpoint_file.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/server/scene/particle_csv.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {
namespace {

using core::InputError;

std::uint32_t sceneMaterial(const core::World& world, const std::string& name, const std::string& field) {
  if (const auto index = world.findMaterial(name)) return *index;
  std::string declared;
  for (const core::Material& m : world.materials()) declared += (declared.empty() ? "" : ", ") + m.name;
  throw InputError(field, core::quotedLogText(name),
                   "material not declared in this scene (declared: " + (declared.empty() ? "none" : declared) + ")");
}

std::size_t addFromCsv(const std::filesystem::path& path, const std::string& prefix, core::World& world) {
  const std::vector<ParticleCsvRecord> records = readParticleCsv(path);
  for (const ParticleCsvRecord& record : records) {
    const std::string where = path.string() + ":line " + std::to_string(record.line);
    core::ParticleSpec spec;
    spec.position = record.position;
    spec.velocity = record.velocity;
    spec.radius = record.radius;
    spec.material = sceneMaterial(world, record.material, where + " column 9 (material)");
    world.addParticle(spec, prefix + ".csv_file[" + where + "]");
  }
  return records.size();
}

std::size_t addFromCheckpoint(const std::filesystem::path& path, const std::string& prefix, core::World& world) {
  const core::CheckpointParticles saved = core::readCheckpointParticles(path);
  if (saved.particles.empty()) throw InputError(prefix + ".checkpoint_file", path.string(), "holds no particles");
  std::vector<std::uint32_t> mapped(saved.material_names.size(), 0);
  std::vector<bool> used(saved.material_names.size(), false);
  for (const core::ParticleSpec& spec : saved.particles) used[spec.material] = true;
  for (std::size_t k = 0; k < mapped.size(); ++k) {
    if (used[k]) mapped[k] = sceneMaterial(world, saved.material_names[k], prefix + ".checkpoint_file material");
  }
  for (std::size_t i = 0; i < saved.particles.size(); ++i) {
    core::ParticleSpec spec = saved.particles[i];
    spec.material = mapped[spec.material];
    world.addParticle(spec, prefix + ".checkpoint_file[id " + std::to_string(saved.ids[i]) + "]");
  }
  return saved.particles.size();
}

}  // namespace

std::size_t addParticleSystem(const v1::ParticleSystem& system, const FileScope& files,
                              const std::string& fieldPrefix, core::World& world) {
  switch (system.source_case()) {
    case v1::ParticleSystem::kCsvFile: {
      const std::string field = fieldPrefix + ".csv_file";
      return addFromCsv(resolveExistingSceneFile(system.csv_file(), files, field), fieldPrefix, world);
    }
    case v1::ParticleSystem::kCheckpointFile: {
      const std::string field = fieldPrefix + ".checkpoint_file";
      return addFromCheckpoint(resolveExistingSceneFile(system.checkpoint_file(), files, field), fieldPrefix,
                               world);
    }
    case v1::ParticleSystem::SOURCE_NOT_SET: break;
  }
  throw InputError(fieldPrefix, "(no source)", "give csv_file or checkpoint_file");
}

}  // namespace demlink::server
