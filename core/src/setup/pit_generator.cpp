/// PitGenerator (method and rationale in pit_generator.hpp).
#include "demlink/core/setup/pit_generator.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "demlink/core/bonds/clods.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/random.hpp"
#include "demlink/core/world.hpp"

namespace demlink::core {
namespace {

constexpr double kSpacingPerRadius = 2.3;  ///< lattice spacing / r_max [-]
constexpr double kJitterPerRadius = 0.05;  ///< jitter amplitude / r_max [-]
constexpr double kMaxRainedParticles = 2.0e6;

/// What is rained: sphere sizes or one clump template [m, m^3].
struct Grain {
  double r_min = 0.0;        ///< smallest (member) radius [m]
  double r_max = 0.0;        ///< largest radius, or the clump's bounding radius [m]
  double mean_volume = 0.0;  ///< [m^3]
  double mean_diameter = 0.0;  ///< for the default kinetic energy threshold [m]
};

Grain grainOf(const PitSpec& spec, const ClumpTemplate* shape) {
  if (shape != nullptr) return {shape->minRadius(), shape->boundingRadius(), shape->volume(), 2.0 * shape->boundingRadius()};
  return {spec.sizes.minRadius(), spec.sizes.maxRadius(), spec.sizes.meanVolume(), 2.0 * spec.sizes.meanRadius()};
}

/// Box and target height fit a grain of largest radius rMax [m].
void checkFit(const PitSpec& spec, double rMax, const std::string& prefix) {
  const double diameter = 2.0 * rMax;
  for (int k = 0; k < 2; ++k) {
    if (spec.upper[k] - spec.lower[k] < kSpacingPerRadius * rMax) {
      throw InputError(prefix + ".upper[" + std::to_string(k) + "]", formatValue(spec.upper[k]),
                       "the box is narrower than " + formatValue(kSpacingPerRadius / 2.0) +
                           " particle diameters (" + formatValue(diameter) + " m each)");
    }
  }
  if (spec.target_height < diameter) {
    throw InputError(prefix + ".target_height", formatValue(spec.target_height),
                     "lower than one particle diameter " + formatValue(diameter) + " m");
  }
}

struct Lattice {
  std::uint32_t nx = 1, ny = 1, nz = 1;
  Vec3 first = Vec3::Zero();  ///< centre of lattice point (0, 0, 0) before jitter [m]
  double spacing = 0.0;       ///< [m]
};

Lattice planLattice(const PitSpec& spec, const Grain& grain, const std::string& prefix) {
  const double rMax = grain.r_max;
  const Vec3 size = spec.upper - spec.lower;
  Lattice l;
  l.spacing = kSpacingPerRadius * rMax;
  auto along = [&](int axis) {
    return static_cast<std::uint32_t>(std::floor((size[axis] - l.spacing) / l.spacing)) + 1;
  };
  l.nx = along(0);
  l.ny = along(1);
  const double needed = spec.overfill * spec.packing_fraction * size.x() * size.y() * spec.target_height /
                        grain.mean_volume;
  const double layers = std::ceil(needed / (static_cast<double>(l.nx) * static_cast<double>(l.ny)));
  if (layers * l.nx * l.ny > kMaxRainedParticles) {
    throw InputError(prefix + (spec.clump_template ? ".clump_template" : ".sizes"),
                     "mean volume " + formatValue(grain.mean_volume) + " m^3",
                     "the pit would need about " + formatValue(layers * l.nx * l.ny) + " particles (limit " +
                         formatValue(kMaxRainedParticles) + "); use larger particles or a smaller pit");
  }
  l.nz = static_cast<std::uint32_t>(std::max(1.0, layers));
  const Vec3 span(static_cast<double>(l.nx - 1) * l.spacing, static_cast<double>(l.ny - 1) * l.spacing, 0.0);
  l.first = Vec3(spec.lower.x() + 0.5 * (size.x() - span.x()), spec.lower.y() + 0.5 * (size.y() - span.y()),
                 spec.lower.z() + 0.5 * l.spacing);
  return l;
}

/// The critical time-step limit for the pit's particles in a world with `settings`.
double criticalLimit(const SimulationSettings& settings, const Material& material, double minRadius,
                     const std::string& prefix) {
  SimulationSettings probeSettings = settings;
  probeSettings.allow_unsafe_time_step = true;
  World probe(probeSettings);
  probe.addMaterial(material);
  probe.declareFutureParticles(0, minRadius, prefix);
  probe.initialize();
  return probe.timeStepReport().limit;
}


/// Copies the spheres whose top is at or below `surface` into `world`, in id order.
void keepSpheres(World& world, const World& pit, const PitSpec& spec, double surface, PitReport& report,
                 const std::string& prefix) {
  const ParticleArrays& p = pit.particles();
  std::vector<std::size_t> order(p.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  report.bed_top = spec.lower.z();
  for (std::size_t i : order) {
    const Vec3& x = p.position[i];
    const bool inside = (x.array() >= spec.lower.array()).all() && x.x() <= spec.upper.x() && x.y() <= spec.upper.y();
    if (!inside || x.z() + p.radius[i] > surface) continue;
    ParticleSpec sphere;
    sphere.position = x;
    sphere.radius = p.radius[i];
    sphere.material = spec.material;
    world.addParticle(sphere, prefix);
    ++report.kept;
    report.kept_mass += world.particles().mass.back();
    report.bed_top = std::max(report.bed_top, x.z() + p.radius[i]);
  }
}

/// Copies the clumps whose highest member top is at or below `surface` (and COM in
/// the box) into `world` at rest, in clump id order, same COM and orientation.
void keepClumps(World& world, const World& pit, const PitSpec& spec, double surface, PitReport& report,
                const std::string& prefix) {
  const ParticleArrays& p = pit.particles();
  std::vector<const ClumpBody*> order;
  for (const ClumpBody& body : pit.clumps()) order.push_back(&body);
  std::sort(order.begin(), order.end(), [](const ClumpBody* a, const ClumpBody* b) { return a->id < b->id; });
  report.bed_top = spec.lower.z();
  for (const ClumpBody* body : order) {
    const Vec3& x = body->position;
    const bool inside = (x.array() >= spec.lower.array()).all() && x.x() <= spec.upper.x() && x.y() <= spec.upper.y();
    double top = -std::numeric_limits<double>::infinity();  // [m]
    for (std::uint32_t slot : body->member_slots) top = std::max(top, p.position[slot].z() + p.radius[slot]);
    if (!inside || top > surface) continue;
    const ClumpTemplate& shape = pit.clumpTemplates()[body->template_index];
    ClumpSpec clump;
    clump.template_index = *spec.clump_template;
    clump.material = spec.material;
    clump.position = x;
    // ClumpBody::orientation maps the body (principal) frame, ClumpSpec::orientation
    // the template frame: body = spec * principal, so spec = body * principal^-1.
    clump.orientation = body->orientation * shape.principalRotation().conjugate();
    world.addClump(clump, prefix);
    ++report.kept;
    report.kept_mass += world.clumps().back().mass;
    report.bed_top = std::max(report.bed_top, top);
  }
}

}  // namespace

void PitSpec::validate(const std::string& prefix, double clumpBoundingRadius) const {
  for (int k = 0; k < 3; ++k) {
    requireFinite(prefix + ".lower[" + std::to_string(k) + "]", lower[k]);
    requireFinite(prefix + ".upper[" + std::to_string(k) + "]", upper[k]);
    if (!(upper[k] > lower[k])) {
      throw InputError(prefix + ".upper[" + std::to_string(k) + "]", formatValue(upper[k]),
                       "must exceed lower[" + std::to_string(k) + "] = " + formatValue(lower[k]) +
                           " (empty or inverted box)");
    }
  }
  if (!clump_template) sizes.validate(prefix + ".sizes");
  const double height = upper.z() - lower.z();
  requirePositive(prefix + ".target_height", target_height);
  if (target_height > height) {
    throw InputError(prefix + ".target_height", formatValue(target_height),
                     "exceeds the box height " + formatValue(height) + " m");
  }
  if (!clump_template) {
    checkFit(*this, sizes.maxRadius(), prefix);
  } else if (clumpBoundingRadius > 0.0) {
    checkFit(*this, clumpBoundingRadius, prefix);
  }
  requireHalfOpenRange(prefix + ".packing_fraction", packing_fraction, 0.0, 0.75);
  requireFinite(prefix + ".overfill", overfill);
  if (overfill < 1.0) throw InputError(prefix + ".overfill", formatValue(overfill), "must be >= 1");
  requireNonNegative(prefix + ".kinetic_energy_threshold", kinetic_energy_threshold);
  requireNonNegative(prefix + ".max_settle_time", max_settle_time);
  requireFinite(prefix + ".clod_fraction", clod_fraction);
  if (clod_fraction < 0.0 || clod_fraction > 1.0) {
    throw InputError(prefix + ".clod_fraction", formatValue(clod_fraction), "must be in [0, 1]");
  }
  if (clod_fraction > 0.0) {
    if (clump_template) {
      throw InputError(prefix + ".clod_fraction", formatValue(clod_fraction),
                       "clods join spheres; a pit of clumps (clump_template) has none");
    }
    requirePositive(prefix + ".clod_radius", clod_radius);
    requireNonNegative(prefix + ".clod_gap", clod_gap);
  } else if (clod_radius != 0.0) {
    throw InputError(prefix + ".clod_radius", formatValue(clod_radius), "needs clod_fraction > 0");
  }
}

namespace {

/// Groups the spheres kept from slot `first` on into clods (pit_generator.hpp).
void formPitClods(const World& world, const PitSpec& spec, std::size_t first, PitReport& report) {
  const ParticleArrays& p = world.particles();
  std::vector<char> kept(p.size(), 0);
  std::fill(kept.begin() + static_cast<std::ptrdiff_t>(first), kept.end(), 1);
  // Its own stream: the clods must not change the bed, which the pit's seed also draws.
  const ClodSpec clods{spec.clod_fraction, spec.clod_radius, spec.clod_gap, spec.seed ^ 0xC10D5C10D5C10D5ULL};
  const std::vector<std::uint32_t> clodOf = formClods(p, kept, clods);
  for (std::size_t i = first; i < p.size(); ++i) {
    if (clodOf[i] == 0) continue;
    report.clod_members.emplace_back(p.id[i], clodOf[i]);
    report.clods = std::max(report.clods, clodOf[i]);
  }
}

}  // namespace

PitReport generatePit(World& world, const PitSpec& spec, const std::string& name, const std::string& prefix) {
  const ClumpTemplate* shape = nullptr;
  if (spec.clump_template) {
    if (*spec.clump_template >= world.clumpTemplates().size()) {
      throw InputError(prefix + ".clump_template", std::to_string(*spec.clump_template), "no such clump template");
    }
    shape = &world.clumpTemplates()[*spec.clump_template];
  }
  spec.validate(prefix, shape != nullptr ? shape->boundingRadius() : 0.0);
  if (spec.material >= world.materials().size()) {
    throw InputError(prefix + ".material", std::to_string(spec.material), "no such material");
  }
  const Material& material = world.materials()[spec.material];
  const Grain grain = grainOf(spec, shape);
  const Lattice lattice = planLattice(spec, grain, prefix);
  const double rMax = grain.r_max;

  // Private world: |g| along -z, the main world's law; walls of the pit material.
  const double g = world.settings().gravity.norm() > 0.0 ? world.settings().gravity.norm() : 9.81;  // [m/s^2]
  const double rainTop = lattice.first.z() + static_cast<double>(lattice.nz - 1) * lattice.spacing + rMax;
  const double fallTime = std::sqrt(2.0 * (rainTop - spec.lower.z()) / g);  // [s]
  SimulationSettings settings;
  settings.gravity = Vec3(0.0, 0.0, -g);
  settings.contact_model = world.settings().contact_model;
  settings.linear_normal_stiffness = world.settings().linear_normal_stiffness;
  settings.threads = world.settings().threads;
  settings.max_impact_velocity = std::max(world.settings().max_impact_velocity, g * fallTime);
  // The whole limit: it already holds the delivered restitution within the engine's default
  // tolerance (1 %) at the rain's impact speed. Half of it took twice the steps for beds
  // whose packing differed by less than two seed deviations (seeds 5-7 of the excavator
  // site, docs/benchmarks.md).
  settings.time_step = criticalLimit(settings, material, grain.r_min, prefix);
  World pit(settings);
  pit.addMaterial(material);
  const std::uint32_t pitShape = shape != nullptr ? pit.addClumpTemplate(*shape, prefix) : 0;
  const Vec3& lo = spec.lower;
  const Vec3& hi = spec.upper;
  pit.addPlane({"floor", lo, Vec3::UnitZ(), 0}, prefix);
  pit.addPlane({"x_lower", lo, Vec3::UnitX(), 0}, prefix);
  pit.addPlane({"x_upper", hi, -Vec3::UnitX(), 0}, prefix);
  pit.addPlane({"y_lower", lo, Vec3::UnitY(), 0}, prefix);
  pit.addPlane({"y_upper", hi, -Vec3::UnitY(), 0}, prefix);

  Random rng(spec.seed);
  const double jitter = kJitterPerRadius * rMax;
  for (std::uint32_t iz = 0; iz < lattice.nz; ++iz) {
    for (std::uint32_t iy = 0; iy < lattice.ny; ++iy) {
      for (std::uint32_t ix = 0; ix < lattice.nx; ++ix) {
        Vec3 point = lattice.first + lattice.spacing * Vec3(static_cast<double>(ix), static_cast<double>(iy), static_cast<double>(iz));
        if (shape != nullptr) {
          for (int k = 0; k < 3; ++k) point[k] += rng.uniform(-jitter, jitter);
          ClumpSpec clump;
          clump.template_index = pitShape;
          clump.material = 0;
          clump.position = point;
          clump.orientation = uniformRotation(rng);
          pit.addClump(clump, prefix);
          continue;
        }
        ParticleSpec sphere;
        sphere.material = 0;
        sphere.radius = spec.sizes.sample(rng);
        sphere.position = point;
        for (int k = 0; k < 3; ++k) sphere.position[k] += rng.uniform(-jitter, jitter);
        pit.addParticle(sphere, prefix);
      }
    }
  }

  PitReport report;
  report.rained = shape != nullptr ? pit.clumps().size() : pit.particles().size();
  const double meanMass = material.density * grain.mean_volume;  // [kg]
  report.threshold = spec.kinetic_energy_threshold > 0.0 ? spec.kinetic_energy_threshold
                                                         : 1.0e-4 * meanMass * g * grain.mean_diameter;
  const double maxTime = spec.max_settle_time > 0.0 ? spec.max_settle_time : 10.0 * fallTime;
  const double dt = settings.time_step;
  const auto checkEvery = static_cast<std::uint64_t>(std::max(1.0, std::round(0.01 * fallTime / dt)));
  const auto maxSteps = static_cast<std::uint64_t>(std::ceil(maxTime / dt));
  spdlog::info("pit_generator {}: settling {} particles ({} x {} x {} lattice, r {:.4g}..{:.4g} m), dt {:.3g} s, "
               "fall time {:.3g} s, kinetic energy threshold {:.3g} J per particle",
               name, report.rained, lattice.nx, lattice.ny, lattice.nz, grain.r_min, rMax, dt, fallTime,
               report.threshold);
  pit.initialize();
  using Clock = std::chrono::steady_clock;
  const Clock::time_point settleStart = Clock::now();
  Clock::time_point lastLog = settleStart;
  const double count = static_cast<double>(report.rained);
  while (pit.stepCount() < maxSteps) {
    // Whole check intervals in one call: the steps between checks fuse their kicks.
    pit.advance(std::min(checkEvery - pit.stepCount() % checkEvery, maxSteps - pit.stepCount()));
    report.final_mean_kinetic_energy = pit.kineticEnergy() / count;
    if (pit.time() >= fallTime && report.final_mean_kinetic_energy < report.threshold) {
      report.settled = true;
      break;
    }
    if (std::chrono::duration<double>(Clock::now() - lastLog).count() >= 2.0) {
      spdlog::info("pit_generator {}: settling t = {:.3f} s (at most {:.3f} s), kinetic energy {:.3g} J per particle",
                   name, pit.time(), maxTime, report.final_mean_kinetic_energy);
      lastLog = Clock::now();
    }
  }
  report.settle_wall_seconds = std::chrono::duration<double>(Clock::now() - settleStart).count();
  report.settle_time = pit.time();
  report.settle_steps = pit.stepCount();
  report.final_mean_kinetic_energy = pit.kineticEnergy() / count;
  if (!report.settled) {
    spdlog::warn("pit_generator {}: not settled after {:.3f} s (kinetic energy {:.3g} J per particle > {:.3g}); "
                 "using the bed as it is",
                 name, report.settle_time, report.final_mean_kinetic_energy, report.threshold);
  }

  const double surface = spec.lower.z() + spec.target_height;
  if (shape != nullptr) {
    keepClumps(world, pit, spec, surface, report, prefix);
  } else {
    const std::size_t first = world.particles().size();
    keepSpheres(world, pit, spec, surface, report, prefix);
    if (spec.clod_fraction > 0.0) formPitClods(world, spec, first, report);
  }
  const Vec3 size = spec.upper - spec.lower;
  report.packing_fraction = report.kept_mass / material.density / (size.x() * size.y() * spec.target_height);
  spdlog::info("pit_generator {}: settled in {:.3f} s ({} steps, {:.3g} s wall); kept {} of {} {} ({:.6g} kg), "
               "bed top {:.4g} m (target {:.4g} m), packing fraction {:.4f} below the target",
               name, report.settle_time, report.settle_steps, report.settle_wall_seconds, report.kept, report.rained,
               shape != nullptr ? "clumps" : "particles", report.kept_mass, report.bed_top, surface,
               report.packing_fraction);
  if (spec.clod_fraction > 0.0) {
    spdlog::info("pit_generator {}: {} clods of radius {:.4g} m hold {} of the {} spheres ({:.4f}, asked {:.4f})", name,
                 report.clods, spec.clod_radius, report.clod_members.size(), report.kept,
                 report.kept > 0 ? static_cast<double>(report.clod_members.size()) / static_cast<double>(report.kept)
                                 : 0.0,
                 spec.clod_fraction);
  }
  if (report.bed_top < surface - 2.0 * rMax) {
    spdlog::warn("pit_generator {}: the bed reaches only {:.4g} m, below the target {:.4g} m; raise overfill or "
                 "packing_fraction",
                 name, report.bed_top, surface);
  }
  return report;
}

}  // namespace demlink::core
