/// ParticleSource (contract and rationale in particle_source.hpp).
///
/// Placement: per inserting step, a Placement gathers what a new sphere could touch:
/// the particles whose centre is within (region bounding radius + largest new radius
/// + own radius) of the region centre, hashed into cells of twice the largest radius
/// involved (so an overlap partner is always in one of the 27 cells around); the
/// planes; the mesh triangles within that distance. Spheres placed in the same step
/// are added to the hash. A candidate is clear when its gap to everything is >= 0.
#include "demlink/core/components/particle_source.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "demlink/core/components/component_state.hpp"
#include "demlink/core/base/input_bounds.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/particles/sphere.hpp"
#include "demlink/core/base/unit_quaternion.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/geometry/triangle_geometry.hpp"
#include "demlink/core/components/component_world.hpp"

namespace demlink::core {
namespace {

/// Time in [start, stop] elapsed since start at time t [s].
double activeTime(double t, double start, double stop) { return std::max(0.0, std::min(t, stop) - start); }

}  // namespace

// ---------------------------------------------------------------- region

void SourceRegion::validate(const std::string& prefix, double largestRadius) const {
  const std::string kindPrefix = prefix + (kind == Kind::Box ? ".box" : ".disc");
  requireFiniteVector(kindPrefix + ".centre", centre);
  (void)requireUnitQuaternion(kindPrefix + ".orientation", orientation);
  if (!(quaternionNorm(orientation) > 1.0e-12)) {
    throw InputError(kindPrefix + ".orientation", "(0, 0, 0, 0)", "must be a non-zero quaternion (or normal)");
  }
  if (kind == Kind::Box) {
    for (int k = 0; k < 3; ++k) {
      const std::string field = kindPrefix + ".half_extents[" + std::to_string(k) + "]";
      requirePositive(field, half_extents[k]);
      if (half_extents[k] < largestRadius) {
        throw InputError(field, formatValue(half_extents[k]),
                         "the box is thinner than the largest particle (radius " + formatValue(largestRadius) +
                             " m); no particle could be placed inside it");
      }
    }
  } else {
    requirePositive(kindPrefix + ".radius", radius);
    requireNonNegative(kindPrefix + ".thickness", thickness);
    if (radius < largestRadius) {
      throw InputError(kindPrefix + ".radius", formatValue(radius),
                       "smaller than the largest particle radius " + formatValue(largestRadius) + " m");
    }
  }
}

double SourceRegion::boundingRadius() const {
  if (kind == Kind::Box) return half_extents.norm();
  return std::hypot(radius, 0.5 * thickness);
}

Vec3 SourceRegion::samplePoint(Random& rng, double r) const {
  Vec3 local;
  if (kind == Kind::Box) {
    for (int k = 0; k < 3; ++k) {
      const double free = std::max(0.0, half_extents[k] - r);
      local[k] = rng.uniform(-free, free);
    }
  } else {
    // Uniform in the disc of radius R - r by rejection from the square (no trigonometry,
    // so the same on every C library); acceptance pi/4.
    const double free = std::max(0.0, radius - r);
    double x = 0.0;
    double y = 0.0;
    do {
      x = rng.uniform(-1.0, 1.0);
      y = rng.uniform(-1.0, 1.0);
    } while (x * x + y * y > 1.0);
    const double axial = std::max(0.0, 0.5 * thickness - r);
    local = Vec3(free * x, free * y, axial > 0.0 ? rng.uniform(-axial, axial) : 0.0);
  }
  return centre + orientation * local;
}

// ---------------------------------------------------------------- spec

void requireSourceRate(const std::string& field, double rate, bool perParticle) {
  requireNonNegative(field, rate);
  const double bound = perParticle ? kMaxSourceParticleRate : kMaxSourceMassRate;
  if (!(rate <= bound)) {
    throw InputError(field, formatValue(rate),
                     "must be at most " + formatValue(bound) + (perParticle ? " particles/s" : " kg/s"));
  }
}

void ParticleSourceSpec::validate(const std::string& prefix, double clumpBoundingRadius) const {
  if (rate_particles_per_s.has_value() == rate_kg_per_s.has_value()) {
    throw InputError(prefix + ".rate_particles_per_s",
                     rate_particles_per_s ? "both rates given" : "neither rate given",
                     "give exactly one of rate_particles_per_s and rate_kg_per_s");
  }
  if (rate_particles_per_s) requireSourceRate(prefix + ".rate_particles_per_s", *rate_particles_per_s, true);
  if (rate_kg_per_s) requireSourceRate(prefix + ".rate_kg_per_s", *rate_kg_per_s, false);
  requireNonNegative(prefix + ".start_time", start_time);
  if (!(stop_time > start_time)) {
    throw InputError(prefix + ".stop_time", formatValue(stop_time),
                     "must be later than start_time = " + formatValue(start_time));
  }
  if (shape == SourceShape::ClumpTemplate) {
    region.validate(prefix, clumpBoundingRadius);
  } else {
    sizes.validate(prefix + ".sizes");
    region.validate(prefix, sizes.maxRadius());
  }
  requireFiniteVector(prefix + ".velocity", velocity);
  requireFiniteVector(prefix + ".angular_velocity", angular_velocity);
  if (max_attempts == 0) throw InputError(prefix + ".max_attempts", "0", "must be >= 1");
}

// ---------------------------------------------------------------- placement

/// Everything a new sphere in this step's region could touch (see the file comment).
class ParticleSource::Placement {
 public:
  Placement(const ComponentWorld& world, const Vec3& regionCentre, double regionRadius, double newRadiusMax)
      : origin_(regionCentre) {
    const ParticleArrays& p = world.particles();
    double largest = newRadiusMax;
    const double reach = regionRadius + newRadiusMax;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double limit = reach + p.radius[i];
      if ((p.position[i] - origin_).squaredNorm() < limit * limit) {
        position_.push_back(p.position[i]);
        radius_.push_back(p.radius[i]);
        largest = std::max(largest, p.radius[i]);
      }
    }
    // Cells of twice the largest radius; never so small that cell indices outgrow 20 bits.
    cell_ = std::max(2.0 * largest, 2.0 * (reach + largest) / 1.0e6);
    for (std::size_t k = 0; k < position_.size(); ++k) bucket(position_[k]).push_back(static_cast<std::uint32_t>(k));
    for (const PlaneWall& wall : world.planes()) planes_.push_back({wall.spec.point, wall.spec.normal});
    for (const MeshBody& mesh : world.meshes()) {
      const std::vector<Vec3>& v = mesh.worldVertices();
      for (const auto& tri : mesh.triangles()) {
        const Vec3& a = v[tri[0]];
        const Vec3& b = v[tri[1]];
        const Vec3& c = v[tri[2]];
        if ((closestPointOnTriangle(origin_, a, b, c).point - origin_).norm() < reach) triangles_.push_back({a, b, c});
      }
    }
  }

  /// True when a sphere (x, r) has a gap >= 0 to every particle, plane and triangle.
  [[nodiscard]] bool clear(const Vec3& x, double r) const {
    for (const auto& [point, normal] : planes_) {
      if ((x - point).dot(normal) < r) return false;
    }
    for (const auto& t : triangles_) {
      if ((closestPointOnTriangle(x, t[0], t[1], t[2]).point - x).squaredNorm() < r * r) return false;
    }
    const std::array<std::int64_t, 3> c = cellOf(x);
    for (std::int64_t dz = -1; dz <= 1; ++dz) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == cells_.end()) continue;
          for (std::uint32_t k : it->second) {
            const double contact = r + radius_[k];
            if ((position_[k] - x).squaredNorm() < contact * contact) return false;
          }
        }
      }
    }
    return true;
  }

  void add(const Vec3& x, double r) {
    position_.push_back(x);
    radius_.push_back(r);
    bucket(x).push_back(static_cast<std::uint32_t>(position_.size() - 1));
  }

 private:
  [[nodiscard]] std::array<std::int64_t, 3> cellOf(const Vec3& x) const {
    std::array<std::int64_t, 3> c{};
    for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(k)] = static_cast<std::int64_t>(std::floor((x[k] - origin_[k]) / cell_));
    return c;
  }
  static std::uint64_t key(const std::array<std::int64_t, 3>& c) {
    constexpr std::int64_t kOffset = 1 << 20;
    std::uint64_t k = 0;
    for (std::int64_t v : c) k = (k << 21) | static_cast<std::uint64_t>(std::clamp<std::int64_t>(v + kOffset, 0, (1 << 21) - 1));
    return k;
  }
  std::vector<std::uint32_t>& bucket(const Vec3& x) { return cells_[key(cellOf(x))]; }

  Vec3 origin_;
  double cell_ = 1.0;
  std::vector<Vec3> position_;
  std::vector<double> radius_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
  std::vector<std::pair<Vec3, Vec3>> planes_;
  std::vector<std::array<Vec3, 3>> triangles_;
};

// ---------------------------------------------------------------- source

ParticleSource::ParticleSource(std::string name, ParticleSourceSpec spec, std::string fieldPrefix)
    : WorldComponent(std::move(name)), spec_(std::move(spec)), field_prefix_(std::move(fieldPrefix)), rng_(spec_.seed) {
  spec_.validate(field_prefix_);
  spec_.region.orientation = Quat(spec_.region.orientation.coeffs() / quaternionNorm(spec_.region.orientation));
}

void ParticleSource::initialize(ComponentWorld& world) {
  if (spec_.material >= world.materials().size()) {
    throw InputError(field_prefix_ + ".material", std::to_string(spec_.material), "no such material");
  }
  density_ = world.materials()[spec_.material].density;
  if (spec_.shape == SourceShape::ClumpTemplate) {
    if (spec_.clump_template >= world.clumpTemplates().size()) {
      throw InputError(field_prefix_ + ".clump_template", std::to_string(spec_.clump_template),
                       "no such clump template");
    }
    const ClumpTemplate& shape = world.clumpTemplates()[spec_.clump_template];
    clump_radius_ = shape.boundingRadius();
    clump_mass_ = density_ * shape.volume();  // exactly as World::addClump computes it
    spec_.validate(field_prefix_, clump_radius_);
    mean_mass_ = clump_mass_;
  } else {
    mean_mass_ = spec_.sizes.meanMass(density_);
  }
  if (!spec_.attached_mesh.empty()) {
    for (std::size_t m = 0; m < world.meshes().size(); ++m) {
      if (world.meshes()[m].name() == spec_.attached_mesh) mesh_index_ = m;
    }
    if (!mesh_index_) {
      throw InputError(field_prefix_ + ".attached_mesh", "\"" + spec_.attached_mesh + "\"", "no mesh body of that name");
    }
  }
}

std::pair<Vec3, Quat> ParticleSource::regionPose(const ComponentWorld& world) const {
  if (!mesh_index_) return {Vec3::Zero(), Quat::Identity()};
  const MeshBody& mesh = world.meshes()[*mesh_index_];
  return {mesh.position(), mesh.orientation()};
}

ParticleSource::Drawn ParticleSource::draw() {
  if (spec_.shape == SourceShape::ClumpTemplate) return {clump_radius_, clump_mass_};
  const double r = spec_.sizes.sample(rng_);
  return {r, sphereMass(r, density_)};
}

void ParticleSource::insertAndRemove(ComponentWorld& world) {
  const double dt = world.settings().time_step;
  const double active = activeTime(world.time() + dt, spec_.start_time, spec_.stop_time);
  if (active <= 0.0 || world.time() >= spec_.stop_time) return;
  std::optional<Placement> placement;
  auto placeOrCount = [&](const Drawn& shape) {
    if (!placement) {
      const auto [position, orientation] = regionPose(world);
      placement.emplace(world, position + orientation * spec_.region.centre, spec_.region.boundingRadius(),
                        maxNewRadius());
    }
    if (!place(world, *placement, shape)) noteShortfall(shape, world.time());
  };
  // Without a run-time change this is rate x active time exactly (the segment starts at 0).
  const double requested = requestedUntil(world.time() + dt);
  if (spec_.rate_particles_per_s) {
    report_.requested_count = requested;
    report_.requested_mass = report_.requested_count * mean_mass_;
    const double target = std::floor(report_.requested_count);
    std::uint64_t tries = 0;
    while (static_cast<double>(report_.inserted_count + report_.shortfall_count) < target) {
      if (++tries > kMaxSourcePlacementsPerStep) {
        noteBulkShortfall(target - static_cast<double>(report_.inserted_count + report_.shortfall_count), world.time());
        break;
      }
      placeOrCount(draw());
    }
  } else {
    report_.requested_mass = requested;
    report_.requested_count = report_.requested_mass / mean_mass_;
    for (std::uint64_t tries = 0;; ++tries) {
      if (!next_) next_ = draw();
      if (consumed_mass_ + next_->mass > report_.requested_mass) break;
      if (tries == kMaxSourcePlacementsPerStep) {
        const double owedMass = report_.requested_mass - consumed_mass_;
        consumed_mass_ = report_.requested_mass;
        noteBulkShortfall(std::floor(owedMass / mean_mass_), world.time());
        report_.shortfall_mass += owedMass - std::floor(owedMass / mean_mass_) * mean_mass_;
        break;
      }
      consumed_mass_ += next_->mass;
      const Drawn shape = *next_;
      next_.reset();
      placeOrCount(shape);
    }
  }
}

double ParticleSource::rate() const {
  return spec_.rate_particles_per_s ? *spec_.rate_particles_per_s : spec_.rate_kg_per_s.value_or(0.0);
}

double ParticleSource::requestedUntil(double t) const {
  const double activeSince = activeTime(t, spec_.start_time, spec_.stop_time) -
                             activeTime(segment_start_, spec_.start_time, spec_.stop_time);
  return requested_before_ + (enabled_ ? rate() : 0.0) * activeSince;
}

void ParticleSource::closeSegment(double t) {
  requested_before_ = requestedUntil(t);
  segment_start_ = t;
}

void ParticleSource::countInsertedElsewhere(std::uint64_t count, double mass) {
  report_.inserted_count += count;
  report_.inserted_mass += mass;
}

void ParticleSource::setEnabled(const ComponentWorld& world, bool enabled) {
  if (enabled == enabled_) return;
  closeSegment(world.time());
  enabled_ = enabled;
  inputs_changed_ = true;
}

void ParticleSource::setRate(const ComponentWorld& world, double rate, const std::string& field) {
  requireSourceRate(field, rate, spec_.rate_particles_per_s.has_value());
  closeSegment(world.time());
  if (spec_.rate_particles_per_s) {
    spec_.rate_particles_per_s = rate;
  } else {
    spec_.rate_kg_per_s = rate;
  }
  inputs_changed_ = true;
}

void ParticleSource::saveInputs(StateWriter& out) const {
  const std::size_t section = out.beginSection("SRCI");
  out.write(static_cast<std::uint8_t>(enabled_));
  out.write(rate());
  out.write(requested_before_);
  out.write(segment_start_);
  out.endSection(section);
}

void ParticleSource::loadInputs(StateReader& in) {
  StateReader s = componentSection(in, "SRCI", "source_inputs");
  const bool enabled = readFlag(s, "enabled flag");
  const double rate = readNonNegative(s, "rate");
  const double requestedBefore = readNonNegative(s, "request before the rate segment");
  const double segmentStart = readNonNegative(s, "start of the rate segment");
  s.requireEnd();
  enabled_ = enabled;
  if (spec_.rate_particles_per_s) {
    spec_.rate_particles_per_s = rate;
  } else {
    spec_.rate_kg_per_s = rate;
  }
  requested_before_ = requestedBefore;
  segment_start_ = segmentStart;
  inputs_changed_ = true;
}

bool ParticleSource::place(ComponentWorld& world, Placement& placement, const Drawn& shape) {
  const auto [bodyPosition, bodyOrientation] = regionPose(world);
  for (std::uint32_t attempt = 0; attempt < spec_.max_attempts; ++attempt) {
    const Vec3 x = bodyPosition + bodyOrientation * spec_.region.samplePoint(rng_, shape.radius);
    if (!placement.clear(x, shape.radius)) continue;
    Vec3 v = spec_.velocity;
    if (mesh_index_ && spec_.add_body_velocity) v += world.meshes()[*mesh_index_].velocityAt(x);
    if (spec_.shape == SourceShape::Sphere) {
      insertSphere(world, x, v, shape.radius);
    } else {
      insertClump(world, x, v);
    }
    placement.add(x, shape.radius);
    return true;
  }
  return false;
}

void ParticleSource::insertSphere(ComponentWorld& world, const Vec3& position, const Vec3& velocity, double radius) {
  ParticleSpec sphere;
  sphere.position = position;
  sphere.velocity = velocity;
  sphere.angular_velocity = spec_.angular_velocity;
  sphere.radius = radius;
  sphere.material = spec_.material;
  world.addParticle(sphere, field_prefix_);
  ++report_.inserted_count;
  report_.inserted_mass += world.particles().mass.back();
}

double ParticleSource::maxNewRadius() const {
  return spec_.shape == SourceShape::ClumpTemplate ? clump_radius_ : spec_.sizes.maxRadius();
}

void ParticleSource::insertClump(ComponentWorld& world, const Vec3& position, const Vec3& velocity) {
  // The orientation is drawn after the place is found: the bounding sphere does not
  // depend on it, and a rotation composed with a uniform one is uniform.
  ClumpSpec clump;
  clump.template_index = spec_.clump_template;
  clump.material = spec_.material;
  clump.position = position;
  clump.orientation = uniformRotation(rng_);
  clump.velocity = velocity;
  clump.angular_velocity = spec_.angular_velocity;
  world.addClump(clump, field_prefix_);
  ++report_.inserted_count;
  report_.inserted_mass += world.clumps().back().mass;
}

void ParticleSource::noteBulkShortfall(double count, double time) {
  report_.shortfall_count += static_cast<std::uint64_t>(count);
  report_.shortfall_mass += count * mean_mass_;
  spdlog::warn("particle_source {}: at t = {:.6g} s the rate asks for more than {} particles in one step; {:.6g} "
               "particles are counted as shortfall without being tried",
               name(), time, kMaxSourcePlacementsPerStep, count);
}

void ParticleSource::noteShortfall(const Drawn& shape, double time) {
  ++report_.shortfall_count;
  report_.shortfall_mass += shape.mass;
  if (report_.shortfall_count >= 2 * shortfall_logged_) {
    spdlog::warn("particle_source {}: region full at t = {:.6g} s: {} particles ({:.6g} kg) could not be placed "
                 "so far (no free place in {} attempts each); the requested rate is not met",
                 name(), time, report_.shortfall_count, report_.shortfall_mass, spec_.max_attempts);
    shortfall_logged_ = report_.shortfall_count;
  }
}

void ParticleSource::saveState(StateWriter& out) const {
  const std::size_t section = out.beginSection("SRCE");
  writeRandomState(out, rng_);
  out.write(static_cast<std::uint8_t>(next_.has_value()));
  out.write(next_ ? next_->radius : 0.0);
  out.write(next_ ? next_->mass : 0.0);
  out.write(consumed_mass_);
  out.write(report_.inserted_count);
  out.write(report_.inserted_mass);
  out.write(report_.shortfall_count);
  out.write(report_.shortfall_mass);
  out.write(report_.requested_count);
  out.write(report_.requested_mass);
  out.write(shortfall_logged_);
  out.endSection(section);
}

void ParticleSource::loadState(StateReader& in) {
  StateReader s = componentSection(in, "SRCE", "source");
  const RandomState rng = readRandomState(s);
  const bool hasNext = readFlag(s, "pending particle flag");
  Drawn next;
  next.radius = readNonNegative(s, "pending particle radius");
  next.mass = readNonNegative(s, "pending particle mass");
  if (hasNext && !(next.radius > 0.0 && next.mass > 0.0)) {
    s.fail(formatValue(next.radius), "pending particle radius and mass must be > 0");
  }
  const double consumed = readNonNegative(s, "consumed mass");
  SourceReport report;
  report.inserted_count = s.read<std::uint64_t>();
  report.inserted_mass = readNonNegative(s, "inserted mass");
  report.shortfall_count = s.read<std::uint64_t>();
  report.shortfall_mass = readNonNegative(s, "shortfall mass");
  report.requested_count = readNonNegative(s, "requested count");
  report.requested_mass = readNonNegative(s, "requested mass");
  const auto logged = s.read<std::uint64_t>();
  s.requireEnd();
  if (report.inserted_count > std::numeric_limits<std::uint64_t>::max() - report.shortfall_count) {
    s.fail(std::to_string(report.inserted_count), "inserted and shortfall counts overflow");
  }
  rng_.setState(rng);
  next_.reset();
  if (hasNext) next_ = next;
  consumed_mass_ = consumed;
  report_ = report;
  shortfall_logged_ = logged;
}

std::string ParticleSource::summaryLine() const {
  const char* unit = spec_.shape == SourceShape::ClumpTemplate ? "clumps" : "particles";
  return fmt::format("particle_source {}: inserted {} {}, {:.6g} kg; requested {:.6g} {}, {:.6g} kg; "
                     "shortfall {} {}, {:.6g} kg",
                     name(), report_.inserted_count, unit, report_.inserted_mass, report_.requested_count,
                     unit, report_.requested_mass, report_.shortfall_count, unit, report_.shortfall_mass);
}

ParticleSource& addParticleSource(ComponentWorld& world, const std::string& name, ParticleSourceSpec spec,
                                  const std::string& fieldPrefix) {
  auto source = std::make_unique<ParticleSource>(name, std::move(spec), fieldPrefix);
  const ParticleSourceSpec& validated = source->spec();
  double minRadius = 0.0;  // [m]
  if (validated.shape == SourceShape::ClumpTemplate) {
    if (validated.clump_template >= world.clumpTemplates().size()) {
      throw InputError(fieldPrefix + ".clump_template", std::to_string(validated.clump_template),
                       "no such clump template (register it with World::addClumpTemplate first)");
    }
    const ClumpTemplate& shape = world.clumpTemplates()[validated.clump_template];
    validated.validate(fieldPrefix, shape.boundingRadius());
    minRadius = shape.minRadius();
  } else {
    minRadius = validated.sizes.minRadius();
  }
  world.declareFutureParticles(validated.material, minRadius, fieldPrefix);
  return static_cast<ParticleSource&>(world.addComponent(std::move(source)));
}

std::optional<double> ParticleSource::largestSpeed(const ComponentWorld& world) const {
  const double rim = spec_.shape == SourceShape::Sphere ? spec_.sizes.maxRadius()
                                                        : world.clumpTemplates()[spec_.clump_template].boundingRadius();
  double speed = spec_.velocity.norm() + spec_.angular_velocity.norm() * rim;
  if (mesh_index_ && spec_.add_body_velocity && *mesh_index_ < world.meshes().size()) {
    const MeshBody& mesh = world.meshes()[*mesh_index_];
    speed += std::max(mesh.speedLimit(),
                      mesh.linearVelocity().norm() + mesh.angularVelocity().norm() * mesh.boundingRadius());
  }
  return speed;
}

}  // namespace demlink::core
