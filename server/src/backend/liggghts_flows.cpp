/// Sources, sinks and sensors on the LIGGGHTS backend (contract in liggghts_flows.hpp).
#include "demlink/server/backend/liggghts_flows.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <numeric>

#include "demlink/core/components/flow_sensor.hpp"
#include "demlink/core/components/particle_sink.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/core/components/sampled_component.hpp"
#include "demlink/core/base/input_error.hpp"

namespace demlink::server {
namespace {

using Kind = core::SizeDistribution::Kind;

/// Relative probability density of a continuous distribution at r (unnormalised).
double density(const core::SizeDistribution& sizes, double r) {
  switch (sizes.kind) {
    case Kind::Linear: {
      const double t = (r - sizes.r_min) / (sizes.r_max - sizes.r_min);
      return sizes.weight_at_min + (sizes.weight_at_max - sizes.weight_at_min) * t;
    }
    case Kind::Normal: {
      const double z = (r - sizes.mean) / sizes.std;
      return std::exp(-0.5 * z * z);
    }
    default:
      return 1.0;
  }
}

/// Composite Simpson integral of f over [a, b].
double integrate(const std::function<double(double)>& f, double a, double b) {
  constexpr int kIntervals = 64;  // even
  const double h = (b - a) / kIntervals;
  double sum = f(a) + f(b);
  for (int i = 1; i < kIntervals; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * f(a + i * h);
  return sum * h / 3.0;
}

/// LIGGGHTS wants its random seeds to be primes above 10000; a prime derived from ours.
std::uint64_t liggghtsSeed(std::uint64_t seed, std::uint64_t salt) {
  std::uint64_t n = 10007 + (seed * 7919 + salt * 104729) % 1000000;
  const auto isPrime = [](std::uint64_t k) {
    for (std::uint64_t d = 2; d * d <= k; ++d) {
      if (k % d == 0) return false;
    }
    return true;
  };
  while (!isPrime(n)) ++n;
  return n;
}

/// The axis (0, 1, 2) `direction` lies along, or -1.
int axisOf(const core::Vec3& direction) {
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(std::abs(direction[axis]) - 1.0) < 1.0e-12) return axis;
  }
  return -1;
}

template <class Component>
std::vector<Component*> componentsOf(core::World& world) {
  std::vector<Component*> found;
  for (const auto& component : world.components()) {
    if (auto* typed = dynamic_cast<Component*>(component.get())) found.push_back(typed);
  }
  return found;
}

}  // namespace

std::vector<LiggghtsSizeClass> liggghtsSizeClasses(const core::SizeDistribution& sizes) {
  std::vector<LiggghtsSizeClass> classes;
  if (sizes.kind == Kind::Fixed) return {{sizes.radius, 1.0}};
  if (sizes.kind == Kind::Discrete) {
    const double total = sizes.weights.empty() ? static_cast<double>(sizes.radii.size())
                                               : std::accumulate(sizes.weights.begin(), sizes.weights.end(), 0.0);
    for (std::size_t k = 0; k < sizes.radii.size(); ++k) {
      const double weight = sizes.weights.empty() ? 1.0 : sizes.weights[k];
      if (weight > 0.0) classes.push_back({sizes.radii[k], weight / total});
    }
    return classes;
  }
  if (!(sizes.r_max > sizes.r_min)) return {{sizes.r_min, 1.0}};  // a degenerate range is one radius
  const double width = (sizes.r_max - sizes.r_min) / kLiggghtsSizeClasses;
  double total = 0.0;
  for (int k = 0; k < kLiggghtsSizeClasses; ++k) {
    const double a = sizes.r_min + k * width;
    const double b = k + 1 == kLiggghtsSizeClasses ? sizes.r_max : a + width;
    const double probability = integrate([&](double r) { return density(sizes, r); }, a, b);
    if (!(probability > 0.0)) continue;
    const double cubed = integrate([&](double r) { return density(sizes, r) * r * r * r; }, a, b) / probability;
    classes.push_back({std::cbrt(cubed), probability});
    total += probability;
  }
  for (LiggghtsSizeClass& sizeClass : classes) sizeClass.number_fraction /= total;
  return classes;
}

std::string liggghtsInsertFix(std::size_t source, std::uint32_t generation) {
  return generation == 0 ? fmt::format("demlink_source{}", source)
                         : fmt::format("demlink_source{}_{}", source, generation);
}

namespace {

/// The region's volume [m^3] (LIGGGHTS inserts into a volume: a disc has its thickness).
double regionVolume(const core::SourceRegion& region) {
  if (region.kind == core::SourceRegion::Kind::Box) return 8.0 * region.half_extents.prod();
  return std::numbers::pi * region.radius * region.radius * region.thickness;
}

/// The LIGGGHTS region command of `source` (named after its first insertion fix `fix`),
/// or an InputError for what LIGGGHTS cannot insert into as we do.
std::string sourceRegionCommand(const core::ParticleSource& source, const std::string& fix, const std::string& field) {
  const core::ParticleSourceSpec& spec = source.spec();
  if (!spec.attached_mesh.empty()) {
    throw core::InputError(field + ".attached_mesh", spec.attached_mesh,
                           "the LIGGGHTS backend inserts into fixed regions only; run it on the native backend");
  }
  const core::SourceRegion& region = spec.region;
  const core::Vec3& c = region.centre;
  if (region.kind == core::SourceRegion::Kind::Box) {
    if (region.orientation.angularDistance(core::Quat::Identity()) > 1.0e-12) {
      throw core::InputError(field + ".box.orientation", "rotated",
                             "LIGGGHTS's insertion regions are axis-aligned boxes; run it on the native backend");
    }
    const core::Vec3 lo = c - region.half_extents;
    const core::Vec3 hi = c + region.half_extents;
    return fmt::format("region {}_region block {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} units box", fix, lo.x(),
                       hi.x(), lo.y(), hi.y(), lo.z(), hi.z());
  }
  const core::Vec3 normal = region.orientation * core::Vec3::UnitZ();
  const int axis = axisOf(normal);
  if (axis < 0) {
    throw core::InputError(field + ".disc.normal", fmt::format("({}, {}, {})", normal.x(), normal.y(), normal.z()),
                           "LIGGGHTS's insertion cylinders lie along x, y or z; run it on the native backend");
  }
  const double rMax = spec.sizes.maxRadius();
  if (region.thickness < 2.0 * rMax) {
    throw core::InputError(field + ".disc.thickness", core::formatValue(region.thickness),
                           "LIGGGHTS inserts into a volume: give a thickness of at least the largest diameter (" +
                               core::formatValue(2.0 * rMax) + " m)");
  }
  const char* axes = "xyz";
  const int u = (axis + 1) % 3;
  const int w = (axis + 2) % 3;
  // LIGGGHTS's cylinder takes the two other coordinates in x, y, z order.
  const int first = std::min(u, w);
  const int second = std::max(u, w);
  return fmt::format("region {}_region cylinder {} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} units box", fix, axes[axis],
                     c[first], c[second], region.radius, c[axis] - 0.5 * region.thickness,
                     c[axis] + 0.5 * region.thickness);
}

}  // namespace

double liggghtsSourceRate(const core::ParticleSource& source) { return source.enabled() ? source.rate() : 0.0; }

std::string liggghtsInsertCommand(const core::World& world, const core::ParticleSource& source, std::size_t index,
                                  std::uint32_t generation) {
  const core::ParticleSourceSpec& spec = source.spec();
  const double rate = liggghtsSourceRate(source);
  const double dt = world.settings().time_step;
  const double now = world.time();
  if (!(rate > 0.0) || now >= spec.stop_time) return {};
  const std::string base = liggghtsInsertFix(index, 0);  // owns the templates and the region
  const std::string fix = liggghtsInsertFix(index, generation);
  const double materialDensity = world.materials().at(spec.material).density;
  // Each insertion fills at most a tenth of the region (LIGGGHTS under-delivers into a
  // crowded region), and happens at least every millisecond, so the rate stays smooth.
  const double meanVolume = spec.sizes.meanVolume();
  const double countRate = spec.rate_kg_per_s ? rate / (materialDensity * meanVolume) : rate;  // [1/s]
  const auto most = static_cast<std::uint64_t>(std::max(1.0, std::round(1.0e-3 / dt)));
  const auto every = std::clamp<std::uint64_t>(
      static_cast<std::uint64_t>(std::floor(0.1 * regionVolume(spec.region) / (countRate * dt * meanVolume))), 1, most);
  std::string amount = "nparticles INF";
  if (std::isfinite(spec.stop_time)) {
    // The first fix covers the whole active time (a restored one continues its count from
    // its restart file); a replacement what is left of it at the new rate.
    const double from = generation == 0 ? spec.start_time : std::max(spec.start_time, now);
    const double total = rate * (spec.stop_time - from);
    amount = spec.rate_kg_per_s ? fmt::format("mass {:.17g}", total)
                                : fmt::format("nparticles {}", static_cast<std::uint64_t>(std::llround(total)));
  }
  std::string start;
  const auto startStep = static_cast<std::uint64_t>(std::llround(spec.start_time / dt));
  if (startStep > world.stepCount()) start = fmt::format(" start {}", startStep);
  const core::Vec3& v = spec.velocity;
  const core::Vec3& omega = spec.angular_velocity;
  return fmt::format(
      "fix {} all insert/rate/region seed {} distributiontemplate {}_sizes maxattempt {} {} {} {:.17g} "
      "insert_every {}{} overlapcheck yes all_in yes vel constant {:.17g} {:.17g} {:.17g} "
      "omega constant {:.17g} {:.17g} {:.17g} region {}_region",
      fix, liggghtsSeed(spec.seed, 1000 + generation), base, spec.max_attempts, amount,
      spec.rate_kg_per_s ? "massrate" : "particlerate", rate, every, start, v.x(), v.y(), v.z(), omega.x(), omega.y(),
      omega.z(), base);
}

std::vector<std::string> liggghtsSourceCommands(const core::World& world) {
  std::vector<std::string> commands;
  std::size_t index = 0;
  for (const auto& component : world.components()) {
    const auto* source = dynamic_cast<const core::ParticleSource*>(component.get());
    if (source == nullptr) continue;
    const core::ParticleSourceSpec& spec = source->spec();
    const std::string fix = liggghtsInsertFix(index, 0);
    // Every source gets its templates and region, even one that inserts nothing yet: a
    // client may switch it on or give it a rate at run time (LiggghtsBackend::advanceTo).
    const std::string region = sourceRegionCommand(*source, fix, "particle_source " + source->name());
    const std::vector<LiggghtsSizeClass> classes = liggghtsSizeClasses(spec.sizes);
    const double materialDensity = world.materials().at(spec.material).density;
    std::string distribution;
    for (std::size_t k = 0; k < classes.size(); ++k) {
      const std::string id = fmt::format("{}_size{}", fix, k);
      commands.push_back(fmt::format("fix {} all particletemplate/sphere {} atom_type {} density constant {:.17g} "
                                     "radius constant {:.17g}",
                                     id, liggghtsSeed(spec.seed, 2 * k + 1), spec.material + 1, materialDensity,
                                     classes[k].radius));
      distribution += fmt::format(" {} {:.17g}", id, classes[k].number_fraction);
    }
    commands.push_back(fmt::format("fix {}_sizes all particledistribution/discrete/numberbased {} {}{}", fix,
                                   liggghtsSeed(spec.seed, 0), classes.size(), distribution));
    commands.push_back(region);
    if (std::string insert = liggghtsInsertCommand(world, *source, index, 0); !insert.empty()) {
      commands.push_back(std::move(insert));
    }
    ++index;
  }
  return commands;
}

std::uint64_t liggghtsStride(const core::World& world, std::uint64_t outputEvery) {
  std::uint64_t stride = outputEvery;
  for (const auto& component : world.components()) {
    if (const auto* sampled = dynamic_cast<const core::SampledComponent*>(component.get())) {
      stride = std::gcd(stride, sampled->sampleEvery());
    }
  }
  return stride;
}

void prepareLiggghtsComponents(core::World& world, std::uint64_t stride) {
  for (core::FlowSensor* sensor : componentsOf<core::FlowSensor>(world)) {
    sensor->setObservationSpacing(stride);
    sensor->initialize(world);  // the band of the first stride
  }
}

std::vector<std::uint64_t> runLiggghtsComponents(core::World& world) {
  for (const auto& component : world.components()) {
    if ((component->stages() & core::stageBit(core::Stage::kObserve)) != 0) component->observe(world);
  }
  const std::vector<core::ParticleSink*> sinks = componentsOf<core::ParticleSink>(world);
  if (sinks.empty()) return {};
  std::vector<std::uint64_t> before = world.particles().id;
  for (core::ParticleSink* sink : sinks) sink->insertAndRemove(world);
  std::vector<std::uint64_t> after = world.particles().id;
  std::sort(before.begin(), before.end());
  std::sort(after.begin(), after.end());
  std::vector<std::uint64_t> removed;
  std::set_difference(before.begin(), before.end(), after.begin(), after.end(), std::back_inserter(removed));
  return removed;
}

}  // namespace demlink::server
