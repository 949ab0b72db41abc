/// Sources family translation (see translate_sources.hpp). Schema-level rules are
/// checked here (which of the alternative fields are given); value ranges are
/// checked by the core validators with the schema path as prefix.
#include "demlink/server/scene/translate_sources.hpp"

#include <cmath>
#include <optional>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {
namespace {

using core::InputError;

core::SourceRegion translateBox(const v1::SourceBox& box, const std::string& prefix) {
  core::SourceRegion region;
  region.kind = core::SourceRegion::Kind::Box;
  const bool halves = box.has_centre() || box.has_half_extents();
  const bool corners = box.has_lower() || box.has_upper();
  if (halves && corners) {
    throw InputError(prefix + ".lower", "(given)", "give either centre + half_extents or lower + upper, not both");
  }
  if (corners) {
    if (!box.has_lower()) throw InputError(prefix + ".lower", "(missing)", "required with upper");
    if (!box.has_upper()) throw InputError(prefix + ".upper", "(missing)", "required with lower");
    const core::Vec3 lower = toFiniteVec3(box.lower(), prefix + ".lower");
    const core::Vec3 upper = toFiniteVec3(box.upper(), prefix + ".upper");
    for (int k = 0; k < 3; ++k) {
      if (!(upper[k] > lower[k])) {
        throw InputError(prefix + ".upper[" + std::to_string(k) + "]", core::formatValue(upper[k]),
                         "must exceed lower[" + std::to_string(k) + "] = " + core::formatValue(lower[k]) +
                             " (empty or inverted box)");
      }
    }
    region.centre = 0.5 * (lower + upper);
    region.half_extents = 0.5 * (upper - lower);
  } else {
    if (!box.has_half_extents()) {
      throw InputError(prefix + ".half_extents", "(missing)", "a box needs half_extents (or lower + upper)");
    }
    region.centre = toVec3(box.centre());
    region.half_extents = toVec3(box.half_extents());
  }
  if (box.has_orientation()) region.orientation = toUnitQuat(box.orientation(), prefix + ".orientation");
  return region;
}

core::SourceRegion translateDisc(const v1::SourceDisc& disc, const std::string& prefix) {
  core::SourceRegion region;
  region.kind = core::SourceRegion::Kind::Disc;
  region.centre = toVec3(disc.centre());
  region.radius = disc.radius();
  region.thickness = disc.thickness();
  if (disc.has_normal()) {
    const core::Vec3 normal = toFiniteVec3(disc.normal(), prefix + ".normal");
    if (!(normal.norm() > 0.0)) throw InputError(prefix + ".normal", "(0, 0, 0)", "must be a non-zero vector");
    region.orientation = core::Quat::FromTwoVectors(core::Vec3::UnitZ(), normal.normalized());
  }
  return region;
}

/// The template index named by `name` (field prefix + ".clump_template"), listing the
/// declared templates when the name is unknown.
std::uint32_t resolveClumpTemplate(const std::string& name, const std::string& prefix, const core::World& world) {
  const std::optional<std::uint32_t> index = world.findClumpTemplate(name);
  if (index) return *index;
  std::string declared;
  for (const core::ClumpTemplate& shape : world.clumpTemplates()) declared += (declared.empty() ? "" : ", ") + shape.name();
  throw InputError(prefix + ".clump_template", core::quotedLogText(name),
                   "unknown clump template (declared: " + (declared.empty() ? "none" : declared) + ")");
}

/// Clump template given: sizes must be omitted (the template sets the size).
void requireNoSizesWithClump(bool hasSizes, const std::string& prefix) {
  if (hasSizes) {
    throw InputError(prefix + ".sizes", "(given)", "must be omitted when clump_template is set (the template sets the size)");
  }
}

}  // namespace

core::SizeDistribution translateSizes(const v1::SizeDistribution& sizes, const std::string& prefix) {
  core::SizeDistribution d;
  std::string kindPrefix = prefix;
  switch (sizes.kind_case()) {
    case v1::SizeDistribution::kRadius:
      d = core::SizeDistribution::fixed(sizes.radius());
      break;
    case v1::SizeDistribution::kUniform:
      d = core::SizeDistribution::uniform(sizes.uniform().r_min(), sizes.uniform().r_max());
      kindPrefix += ".uniform";
      break;
    case v1::SizeDistribution::kLinear: {
      const v1::SizeDistribution::Linear& l = sizes.linear();
      d = core::SizeDistribution::linear(l.r_min(), l.r_max(), l.has_weight_at_min() ? l.weight_at_min() : 1.0,
                                         l.has_weight_at_max() ? l.weight_at_max() : 1.0);
      kindPrefix += ".linear";
      break;
    }
    case v1::SizeDistribution::kNormal: {
      const v1::SizeDistribution::Normal& n = sizes.normal();
      d = core::SizeDistribution::normal(n.mean(), n.std(), n.r_min(), n.r_max());
      kindPrefix += ".normal";
      break;
    }
    case v1::SizeDistribution::kDiscrete: {
      const v1::SizeDistribution::Discrete& s = sizes.discrete();
      std::vector<double> radii(s.radii().begin(), s.radii().end());
      std::vector<double> weights(s.weights().begin(), s.weights().end());
      if (weights.empty()) weights.assign(radii.size(), 1.0);
      d = core::SizeDistribution::discrete(std::move(radii), std::move(weights));
      kindPrefix += ".discrete";
      break;
    }
    case v1::SizeDistribution::KIND_NOT_SET:
      throw InputError(prefix, "(missing)", "give one of radius, uniform, linear, normal, discrete");
  }
  d.validate(kindPrefix);
  return d;
}

void addSingleParticle(const v1::SingleParticle& particle, std::uint32_t material, const std::string& prefix,
                       core::World& world) {
  core::requirePositive(prefix + ".diameter", particle.diameter());
  core::ParticleSpec sphere;
  sphere.position = toVec3(particle.position());
  sphere.velocity = toVec3(particle.velocity());
  sphere.angular_velocity = toVec3(particle.angular_velocity());
  sphere.radius = 0.5 * particle.diameter();
  sphere.material = material;
  world.addParticle(sphere, prefix);
}

namespace {

/// The distribution of parcel radii for grain radii `sizes`: every length x `factor`,
/// weights kept.
core::SizeDistribution scaledSizes(core::SizeDistribution sizes, double factor) {
  sizes.radius *= factor;
  sizes.r_min *= factor;
  sizes.r_max *= factor;
  sizes.mean *= factor;
  sizes.std *= factor;
  for (double& r : sizes.radii) r *= factor;
  return sizes;
}

}  // namespace

void addParticleSource(const v1::ParticleSource& source, const std::string& name, std::uint32_t material,
                       const core::CoarseGraining& coarse, const std::string& prefix, core::World& world) {
  core::ParticleSourceSpec spec;
  if (!source.clump_template().empty()) {
    spec.shape = core::SourceShape::ClumpTemplate;
    spec.clump_template = resolveClumpTemplate(source.clump_template(), prefix, world);
    requireNoSizesWithClump(source.has_sizes(), prefix);
  } else {
    if (!source.has_sizes()) throw InputError(prefix + ".sizes", "(missing)", "a particle source needs sizes (or a clump_template)");
    spec.sizes = translateSizes(source.sizes(), prefix + ".sizes");
  }
  switch (source.region_case()) {
    case v1::ParticleSource::kBox: spec.region = translateBox(source.box(), prefix + ".box"); break;
    case v1::ParticleSource::kDisc: spec.region = translateDisc(source.disc(), prefix + ".disc"); break;
    case v1::ParticleSource::REGION_NOT_SET:
      throw InputError(prefix + ".box", "(missing)", "a particle source needs a region: box or disc");
  }
  if (source.has_rate_particles_per_s()) spec.rate_particles_per_s = source.rate_particles_per_s();
  if (source.has_rate_kg_per_s()) spec.rate_kg_per_s = source.rate_kg_per_s();
  spec.start_time = source.start_time();
  if (source.has_stop_time()) spec.stop_time = source.stop_time();
  spec.velocity = toVec3(source.velocity());
  spec.angular_velocity = toVec3(source.angular_velocity());
  spec.attached_mesh = source.attached_mesh();
  if (source.has_add_body_velocity()) spec.add_body_velocity = source.add_body_velocity();
  spec.seed = source.seed();
  if (source.has_max_attempts()) spec.max_attempts = source.max_attempts();
  spec.material = material;
  if (coarse.factor != 1.0) {
    spec.sizes = scaledSizes(spec.sizes, coarse.factor);
    if (spec.rate_particles_per_s) *spec.rate_particles_per_s /= std::pow(coarse.factor, 3);
  }
  core::addParticleSource(world, name, std::move(spec), prefix);
}

core::PitSpec pitSpec(const v1::PitGenerator& pit, std::uint32_t material, const std::string& prefix,
                      const core::World& world) {
  core::PitSpec spec;
  const bool corners = pit.has_lower() || pit.has_upper();
  const bool centred = pit.has_centre() || pit.has_size();
  if (corners == centred) {
    throw InputError(prefix + ".lower", corners ? "(given with centre/size)" : "(missing)",
                     "give the box as lower + upper or as centre + size");
  }
  if (corners) {
    if (!pit.has_lower()) throw InputError(prefix + ".lower", "(missing)", "required with upper");
    if (!pit.has_upper()) throw InputError(prefix + ".upper", "(missing)", "required with lower");
    spec.lower = toVec3(pit.lower());
    spec.upper = toVec3(pit.upper());
  } else {
    if (!pit.has_size()) throw InputError(prefix + ".size", "(missing)", "required with centre");
    const core::Vec3 centre = toVec3(pit.centre());
    const core::Vec3 size = toVec3(pit.size());
    for (int k = 0; k < 3; ++k) core::requirePositive(prefix + ".size[" + std::to_string(k) + "]", size[k]);
    spec.lower = centre - 0.5 * size;
    spec.upper = centre + 0.5 * size;
  }
  if (!pit.clump_template().empty()) {
    spec.clump_template = resolveClumpTemplate(pit.clump_template(), prefix, world);
    requireNoSizesWithClump(pit.has_sizes(), prefix);
  } else {
    if (!pit.has_sizes()) throw InputError(prefix + ".sizes", "(missing)", "a pit generator needs sizes (or a clump_template)");
    spec.sizes = translateSizes(pit.sizes(), prefix + ".sizes");
  }
  spec.target_height = pit.target_height();
  spec.material = material;
  spec.seed = pit.seed();
  if (pit.has_packing_fraction()) spec.packing_fraction = pit.packing_fraction();
  if (pit.has_overfill()) spec.overfill = pit.overfill();
  spec.kinetic_energy_threshold = pit.kinetic_energy_threshold();
  spec.max_settle_time = pit.max_settle_time();
  spec.clod_fraction = pit.clod_fraction();
  spec.clod_radius = pit.clod_radius();
  const core::ClumpTemplate* shape = spec.clump_template ? &world.clumpTemplates()[*spec.clump_template] : nullptr;
  spec.validate(prefix, shape != nullptr ? shape->boundingRadius() : 0.0);
  if (spec.clod_fraction > 0.0 && pit.clod_bonds().empty()) {
    throw InputError(prefix + ".clod_bonds", "\"\"", "required with clod_fraction > 0: the name of a parallel_bonds component");
  }
  if (spec.clod_fraction == 0.0 && !pit.clod_bonds().empty()) {
    throw InputError(prefix + ".clod_bonds", "\"" + pit.clod_bonds() + "\"", "needs clod_fraction > 0");
  }
  return spec;
}

}  // namespace demlink::server
