#include "study_scenes.hpp"

#include <time.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>
#include <random>
#include <stdexcept>

#include "demlink/core/particles/coarse_graining.hpp"
#include "demlink/core/walls/mesh_body.hpp"

namespace demlink::study {
namespace {

using core::Vec3;
using core::World;
using Clock = std::chrono::steady_clock;

constexpr double kReferenceModulus = 1.0e8;  ///< [Pa]
constexpr double kReferenceOrifice = 0.025;  ///< the hopper's orifice hopper_grains is counted for [m]

/// Grains' lengths / the reference grains' [-]: every scene length scales by it.
double lengthScale(const Knobs& knobs) { return knobs.grains.radius_min / kGrainRadius; }

/// Mean grain volume: r uniform in [a, b] has mean r^3 = (b^4 - a^4) / (4 (b - a)) [m^3].
double grainVolume(const Knobs& knobs) {
  const double a = knobs.grains.radius_min, b = knobs.grains.radius_max;
  const double meanCube = b > a ? (std::pow(b, 4) - std::pow(a, 4)) / (4.0 * (b - a)) : a * a * a;
  return 4.0 / 3.0 * std::numbers::pi * meanCube;
}

std::size_t parcels(const Knobs& knobs, std::size_t grains) { return core::CoarseGraining{knobs.coarse}.count(grains); }

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// Least-squares slope of y over x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const auto n = static_cast<double>(x.size());
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  const double denominator = n * sxx - sx * sx;
  return denominator > 0.0 ? (n * sxy - sx * sy) / denominator : std::nan("");
}

/// Solid fraction of the box [lo, hi]: the share of a 24^3 grid of points inside a sphere.
double solidFraction(const core::ParticleArrays& p, const Vec3& lo, const Vec3& hi) {
  constexpr int kPoints = 24;
  std::vector<std::size_t> near;
  double rMax = 0.0;
  for (double r : p.radius) rMax = std::max(rMax, r);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& x = p.position[i];
    if ((x.array() > (lo.array() - rMax)).all() && (x.array() < (hi.array() + rMax)).all()) near.push_back(i);
  }
  std::size_t inside = 0;
  for (int a = 0; a < kPoints; ++a) {
    for (int b = 0; b < kPoints; ++b) {
      for (int c = 0; c < kPoints; ++c) {
        const Vec3 f((a + 0.5) / kPoints, (b + 0.5) / kPoints, (c + 0.5) / kPoints);
        const Vec3 point = lo + (hi - lo).cwiseProduct(f);
        for (std::size_t i : near) {
          if ((p.position[i] - point).squaredNorm() < p.radius[i] * p.radius[i]) {
            ++inside;
            break;
          }
        }
      }
    }
  }
  return static_cast<double>(inside) / (kPoints * kPoints * kPoints);
}

/// Height below which `share` of the particle centres lie [m].
double centreQuantile(const core::ParticleArrays& p, double share) {
  std::vector<double> z;
  z.reserve(p.size());
  for (const Vec3& x : p.position) z.push_back(x.z());
  if (z.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(share * static_cast<double>(z.size() - 1));
  std::nth_element(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(k), z.end());
  return z[k];
}

/// A square plate [0, side]^2 at z = 0 with the square hole side/2 +- hole/2 (normal +z).
core::MeshBody orificePlate(double side, double hole, std::uint32_t material) {
  const double a = 0.5 * (side - hole), b = 0.5 * (side + hole);
  // Outer corners 0-3, inner corners 4-7, both counter-clockwise seen from above.
  std::vector<Vec3> v{{0, 0, 0}, {side, 0, 0}, {side, side, 0}, {0, side, 0},
                      {a, a, 0}, {b, a, 0},    {b, b, 0},       {a, b, 0}};
  std::vector<std::array<std::uint32_t, 3>> t;
  for (std::uint32_t k = 0; k < 4; ++k) {
    const std::uint32_t o0 = k, o1 = (k + 1) % 4, i0 = 4 + k, i1 = 4 + (k + 1) % 4;
    t.push_back({o0, o1, i1});
    t.push_back({o0, i1, i0});
  }
  return core::MeshBody("orifice_plate", std::move(v), std::move(t), material);
}

core::MeshBody boxBody(const std::string& name, const Vec3& lo, const Vec3& hi, std::uint32_t material) {
  core::TriangleMesh box = core::axisAlignedBoxMesh(lo, hi);
  return core::MeshBody(name, std::move(box.vertices), std::move(box.triangles), material);
}

/// Side walls of the box [0, far.x] x [0, far.y].
void addWalls(World& world, const Vec3& far) {
  world.addPlane({"x0", Vec3::Zero(), Vec3::UnitX(), 0});
  world.addPlane({"x1", far, -Vec3::UnitX(), 0});
  world.addPlane({"y0", Vec3::Zero(), Vec3::UnitY(), 0});
  world.addPlane({"y1", far, -Vec3::UnitY(), 0});
}

/// Grains of a scene whose footprint area grows by `scale` [-].
std::size_t scaledCount(std::size_t grains, double scale) {
  return static_cast<std::size_t>(std::lround(static_cast<double>(grains) * scale));
}

void finish(SceneResult& result, const World& world, Clock::time_point start) {
  result.wall = secondsSince(start);
  result.simulated = world.time();
}

}  // namespace

Grains referenceGrains() {
  Grains g;
  g.material.name = "grains";
  g.material.density = 2500.0;
  g.material.youngs_modulus = kReferenceModulus;
  g.material.poisson_ratio = 0.3;
  g.material.restitution = 0.5;
  g.material.sliding_friction = 0.5;
  g.material.rolling_friction = 0.1;
  return g;
}

core::Material studyMaterial(const Knobs& knobs) {
  core::Material m = knobs.grains.material;
  m.youngs_modulus *= knobs.modulus_scale;
  return m;
}

double parcelRadius(const Knobs& knobs) { return core::CoarseGraining{knobs.coarse}.radius(knobs.grains.radius_min); }

double parcelRadiusMax(const Knobs& knobs) {
  return core::CoarseGraining{knobs.coarse}.radius(knobs.grains.radius_max);
}

double criticalLimit(const Knobs& knobs) {
  core::SimulationSettings s;
  s.contact_model = knobs.law;
  // The velocity Verlet limit for every integrator: the integrator knob changes the
  // integrator at the finest setting's step, one knob at a time (explicit Euler's own
  // limit is ~5x smaller, so at 0.1 of Verlet's it runs at ~0.5 of its own).
  s.integrator = core::IntegratorKind::VelocityVerlet;
  s.max_impact_velocity = kImpactSpeed;
  s.restitution_tolerance = kRestitutionTolerance;
  s.time_step = 1e-9;
  World world(s);
  world.addMaterial(studyMaterial(knobs));
  core::ParticleSpec p;
  p.radius = parcelRadius(knobs);
  world.addParticle(p);
  world.initialize();
  return world.timeStepReport().limit;
}

core::SimulationSettings studySettings(const Knobs& knobs) {
  core::SimulationSettings s;
  s.contact_model = knobs.law;
  s.integrator = knobs.integrator;
  s.max_impact_velocity = kImpactSpeed;
  s.restitution_tolerance = kRestitutionTolerance;
  s.time_step = knobs.dt_fraction * criticalLimit(knobs);
  s.allow_unsafe_time_step = true;  // the atlas probes past the limit on purpose
  s.neighbour_skin = knobs.skin_factor * parcelRadius(knobs);
  return s;
}

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void advance(World& world, double until, SceneResult& result, double cpuLimit,
             const std::function<void()>& afterStep) {
  const double cpuStart = threadCpuSeconds();
  const double dt = world.settings().time_step;
  long n = 0;
  while (world.time() < until - 0.5 * dt) {
    world.step();
    result.particle_steps += static_cast<double>(world.particles().size());
    if (afterStep) afterStep();
    if (++n % 2048 == 0 && threadCpuSeconds() - cpuStart > cpuLimit) {
      throw std::runtime_error("CPU-time limit reached at t = " + std::to_string(world.time()) + " s");
    }
  }
  for (const Vec3& x : world.particles().position) {
    if (!x.allFinite()) throw std::runtime_error("non-finite position");
  }
}

double addLattice(World& world, std::size_t count, double radius, double radiusMax, const Vec3& lo, const Vec3& hi,
                  std::uint64_t seed, const std::function<bool(const Vec3&)>& free) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double rMax = radiusMax;
  const double spacing = 2.2 * rMax;
  const double jitter = 0.08 * radius;
  const auto nx = static_cast<std::size_t>(std::max(1.0, std::floor((hi.x() - lo.x()) / spacing)));
  const auto ny = static_cast<std::size_t>(std::max(1.0, std::floor((hi.y() - lo.y()) / spacing)));
  double top = lo.z();
  for (std::size_t k = 0, placed = 0; placed < count; ++k) {
    const auto i = static_cast<double>(k % nx);
    const auto j = static_cast<double>((k / nx) % ny);
    const auto layer = static_cast<double>(k / (nx * ny));
    const Vec3 point(lo.x() + (i + 0.5) * spacing + jitter * (2.0 * u(rng) - 1.0),
                     lo.y() + (j + 0.5) * spacing + jitter * (2.0 * u(rng) - 1.0), lo.z() + (layer + 0.5) * spacing);
    const double r = radius + (radiusMax - radius) * u(rng);
    if (free && !free(point)) continue;
    core::ParticleSpec p;
    p.radius = r;
    p.position = point;
    world.addParticle(p);
    top = std::max(top, point.z());
    ++placed;
  }
  return top;
}

SceneResult runImpact(const Knobs& knobs) {
  SceneResult result("impact");
  const auto start = Clock::now();
  core::SimulationSettings s = studySettings(knobs);
  s.gravity = Vec3::Zero();
  World world(s);
  world.addMaterial(studyMaterial(knobs));
  const double r = parcelRadius(knobs);
  core::ParticleSpec a;
  a.radius = r;
  a.position = Vec3(-(r + 1e-5), 0.0, 0.0);
  a.velocity = Vec3(0.5, 0.0, 0.0);
  core::ParticleSpec b = a;
  b.position = -a.position;
  b.velocity = -a.velocity;
  world.addParticle(a);
  world.addParticle(b);
  world.initialize();
  const auto& p = world.particles();
  // Until the spheres separate; a contact lasts far less than 10 ms.
  for (int n = 0; n < 10'000'000 && world.time() < 0.01; ++n) {
    world.step();
    result.particle_steps += 2.0;
    if ((p.position[1] - p.position[0]).norm() > 2.0 * r + 3e-5) break;
  }
  const double requested = studyMaterial(knobs).restitution;
  result.metrics.emplace_back("restitution_ratio", std::abs(p.velocity[1].x() - p.velocity[0].x()) / requested);
  finish(result, world, start);
  return result;
}

SceneResult runBed(const Knobs& knobs, const Budget& budget, bool cohesive, SettledBed settled) {
  SceneResult result(cohesive ? "bed_cohesive" : "bed");
  const auto start = Clock::now();
  // A box twice as long as wide; the blade starts 3 diameters from the near wall and
  // travels 6 (0.1 m/s for 0.3 s), so its front stops 10 diameters short of the far wall,
  // where the heap it pushes ahead stays clear of the wall.
  const double footprint = std::sqrt(budget.scale * budget.bed_area) * lengthScale(knobs);
  const double length = 0.1 * footprint, width = 0.05 * footprint;  // [m]
  constexpr double kBladeSpeed = 0.1;  // [m/s]
  const double bladeHalfThickness = 0.0015 * lengthScale(knobs);  // [m]
  // The blade spans the box but for gaps no grain fits through (grains wedged between a
  // blade's edge and a wall jam it); it cuts the upper half of the bed, leaving three
  // diameters below it for the grains that pass under it.
  const double sideGap = 0.0005 * lengthScale(knobs);  // [m]
  // Its size follows the bed the grains make (the same for every knob).
  const std::size_t grains = scaledCount(budget.bed_grains, budget.scale);
  const double height = static_cast<double>(grains) * grainVolume(knobs) / (0.6 * length * width);
  const double bladeBottom = 0.5 * height;
  const double bladeX = 0.015 * lengthScale(knobs);
  const double r = parcelRadius(knobs);
  const double clearance = bladeHalfThickness + 1.1 * parcelRadiusMax(knobs);
  // The blade stands in the box while the bed forms around it, so it never appears inside
  // particles.
  auto bedWorld = [&](double cohesionEnergyDensity) {
    World world(studySettings(knobs));
    core::Material material = studyMaterial(knobs);
    material.cohesion_energy_density = core::CoarseGraining{knobs.coarse}.cohesionEnergyDensity(cohesionEnergyDensity);
    world.addMaterial(material);
    world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0});
    addWalls(world, Vec3(length, width, 0.0));
    world.addMesh(boxBody("blade", Vec3(-bladeHalfThickness, -0.5 * width + sideGap, bladeBottom),
                          Vec3(bladeHalfThickness, 0.5 * width - sideGap, 3.0 * height), 0));
    world.mesh(0).setPose(Vec3(bladeX, 0.5 * width, 0.0), core::Quat::Identity());
    addLattice(world, parcels(knobs, grains), r, parcelRadiusMax(knobs), Vec3(0.0, 0.0, 0.0), Vec3(length, width, 0.0), knobs.seed,
               [&](const Vec3& x) { return std::abs(x.x() - bladeX) > clearance || x.z() < bladeBottom - clearance; });
    return world;
  };
  std::string settledHere;
  std::optional<World> dry;
  if (settled.from == nullptr) {
    dry.emplace(bedWorld(0.0));
    dry->initialize();
    advance(*dry, budget.bed_settle, result, budget.cpu_limit);
    std::ostringstream out;
    dry->saveCheckpoint(out);
    settledHere = out.str();
    if (settled.to != nullptr) *settled.to = settledHere;
  }
  const std::string_view settledBed = settled.from != nullptr ? *settled.from : settledHere;
  // The cohesive case wets the same settled bed (a rained cohesive bed would settle looser
  // and hide what cohesion adds). Parcels take k_c through core::CoarseGraining's law.
  std::optional<World> wet;
  if (cohesive) {
    wet.emplace(bedWorld(budget.cohesion_energy_density));
    wet->restoreCheckpoint(settledBed, "dry bed");
  } else if (!dry) {
    dry.emplace(bedWorld(0.0));
    dry->restoreCheckpoint(settledBed, "settled dry bed");
  }
  World& world = cohesive ? *wet : *dry;
  if (!cohesive) {
    // Ahead of the blade's final position, clear of the walls.
    const auto& p = world.particles();
    const double bedTop = centreQuantile(p, 0.95);
    result.metrics.emplace_back("packing_fraction", solidFraction(p, Vec3(0.55 * length, 0.1 * width, 0.2 * bedTop),
                                                                  Vec3(0.9 * length, 0.9 * width, 0.7 * bedTop)));
  }
  world.mesh(0).setVelocity(Vec3(kBladeSpeed, 0.0, 0.0), Vec3::Zero());
  // The drag builds up while the blade's first third of travel loads the bed ahead of it.
  const double dragStart = world.time() + budget.drag_time / 3.0;
  double impulse = 0.0, counted = 0.0;
  const double dt = world.settings().time_step;
  advance(world, budget.bed_settle + budget.drag_time, result, budget.cpu_limit, [&] {
    if (world.time() > dragStart) {
      impulse += -world.meshes()[0].force().x() * dt;
      counted += dt;
    }
  });
  result.metrics.emplace_back("drag_force", counted > 0.0 ? impulse / counted : std::nan(""));
  finish(result, world, start);
  return result;
}

SceneResult runHeap(const Knobs& knobs, const Budget& budget) {
  SceneResult result("heap");
  const auto start = Clock::now();
  const double footprint = 0.04 * std::sqrt(budget.scale) * lengthScale(knobs);  // [m]
  World world(studySettings(knobs));
  world.addMaterial(studyMaterial(knobs));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0});
  const double r = parcelRadius(knobs);
  addLattice(world, parcels(knobs, scaledCount(budget.heap_grains, budget.scale)), r, parcelRadiusMax(knobs),
             Vec3(-0.5 * footprint, -0.5 * footprint, 0.0), Vec3(0.5 * footprint, 0.5 * footprint, 0.0), knobs.seed);
  world.initialize();
  advance(world, budget.heap_time, result, budget.cpu_limit);
  // Heap surface: the highest sphere top in rings about the centre; the angle is the
  // slope of a line through the rings between 20 % and 80 % of the heap's radius.
  const auto& p = world.particles();
  Vec3 centre = Vec3::Zero();
  for (const Vec3& x : p.position) centre += x;
  centre /= static_cast<double>(p.size());
  std::vector<double> distance;
  for (const Vec3& x : p.position) distance.push_back(std::hypot(x.x() - centre.x(), x.y() - centre.y()));
  std::vector<double> sorted = distance;
  std::sort(sorted.begin(), sorted.end());
  const double radius = sorted[static_cast<std::size_t>(0.98 * static_cast<double>(sorted.size() - 1))];
  constexpr int kRings = 10;
  std::vector<double> top(kRings, 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto ring = static_cast<int>(distance[i] / radius * kRings);
    if (ring < kRings) top[static_cast<std::size_t>(ring)] = std::max(top[static_cast<std::size_t>(ring)], p.position[i].z() + p.radius[i]);
  }
  std::vector<double> x, y;
  for (int ring = 2; ring < 8; ++ring) {
    x.push_back((ring + 0.5) / kRings * radius);
    y.push_back(top[static_cast<std::size_t>(ring)]);
  }
  result.metrics.emplace_back("repose_angle_deg", std::atan(-slope(x, y)) * 180.0 / std::numbers::pi);
  result.metrics.emplace_back("heap_height", std::max(top[0], top[1]));
  finish(result, world, start);
  return result;
}

SceneResult runSlump(const Knobs& knobs, const Budget& budget) {
  SceneResult result("slump");
  const auto start = Clock::now();
  const double rMax = parcelRadiusMax(knobs);
  const double spacing = 2.2 * rMax;  // addLattice's
  const std::size_t grains = parcels(knobs, scaledCount(budget.slump_grains, budget.scale));
  // A square column of lattice sites about 1.5 sides deep once settled, sized in sites so
  // that any size distribution gives the same shape.
  const double sites = std::max(2.0, std::round(std::cbrt(static_cast<double>(grains) / 1.5)));
  const double side = sites * spacing;
  const double layers = std::ceil(static_cast<double>(grains) / (sites * sites));
  World world(studySettings(knobs));
  world.addMaterial(studyMaterial(knobs));
  world.addPlane({"floor", Vec3::Zero(), Vec3::UnitZ(), 0});
  // The mould: four walls that stop touching the grains when it is lifted.
  const double t = spacing;  // wall thickness
  const double h = (layers + 2.0) * spacing;
  const std::array<std::pair<Vec3, Vec3>, 4> walls{{{Vec3(-t, -t, 0.0), Vec3(0.0, side + t, h)},
                                                    {Vec3(side, -t, 0.0), Vec3(side + t, side + t, h)},
                                                    {Vec3(0.0, -t, 0.0), Vec3(side, 0.0, h)},
                                                    {Vec3(0.0, side, 0.0), Vec3(side, side + t, h)}}};
  for (std::size_t k = 0; k < walls.size(); ++k) {
    core::MeshBody wall = boxBody("mould_" + std::to_string(k), walls[k].first, walls[k].second, 0);
    wall.setCollisionWindow(0.0, budget.slump_settle);
    world.addMesh(std::move(wall));
  }
  addLattice(world, grains, parcelRadius(knobs), rMax, Vec3::Zero(), Vec3(side, side, 0.0), knobs.seed);
  world.initialize();
  advance(world, budget.slump_settle, result, budget.cpu_limit);
  // Heights as a quantile of the centres: one grain on top does not set them.
  const double settled = centreQuantile(world.particles(), 0.95);
  advance(world, budget.slump_settle + budget.slump_time, result, budget.cpu_limit);
  result.metrics.emplace_back("slump_height_ratio", centreQuantile(world.particles(), 0.95) / settled);
  finish(result, world, start);
  return result;
}

std::size_t hopperGrains(const Knobs& knobs, const Budget& budget) {
  const double grains = static_cast<double>(scaledCount(budget.hopper_grains, budget.scale)) *
                        std::pow(budget.hopper_orifice / kReferenceOrifice / lengthScale(knobs), 3);
  return static_cast<std::size_t>(std::lround(grains));
}

SceneResult runHopper(const Knobs& knobs, const Budget& budget) {
  SceneResult result("hopper");
  const auto start = Clock::now();
  // The orifice is 10 reference grain radii (4.5 mean diameters) unless the budget gives
  // another; the box is 2.4 orifices wide and its lattice keeps its depth in orifices.
  const double orifice = budget.hopper_orifice;  // [m]
  const double side = 2.4 * orifice * std::sqrt(budget.scale);  // [m]
  core::SimulationSettings s = studySettings(knobs);
  s.bounds = core::DomainBounds{Vec3(-0.4 * orifice, -0.4 * orifice, -2.0 * orifice),
                                Vec3(side + 0.4 * orifice, side + 0.4 * orifice, 2.0)};
  World world(s);
  world.addMaterial(studyMaterial(knobs));
  addWalls(world, Vec3::Constant(side));
  world.addMesh(orificePlate(side, orifice, 0));
  core::TriangleMesh gateShape =
      core::rectangleMesh(Vec3(0.5 * side, 0.5 * side, 0.0), 0.58 * orifice, 0.58 * orifice, 1, 1);
  core::MeshBody gate("gate", std::move(gateShape.vertices), std::move(gateShape.triangles), 0);
  gate.setCollisionWindow(0.0, budget.hopper_fill);
  world.addMesh(std::move(gate));
  addLattice(world, parcels(knobs, hopperGrains(knobs, budget)), parcelRadius(knobs),
             parcelRadiusMax(knobs), Vec3(0.0, 0.0, 0.08 * orifice), Vec3(side, side, 0.0), knobs.seed);
  world.initialize();
  advance(world, budget.hopper_fill, result, budget.cpu_limit);
  const auto& p = world.particles();
  auto heldMass = [&] {
    double mass = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.position[i].z() > 0.0) mass += p.mass[i];
    }
    return mass;
  };
  std::vector<double> times, masses;
  const double sampleEvery = 0.01;  // [s]
  const double firstSample = budget.hopper_fill + std::min(0.05, 0.25 * budget.hopper_flow);
  for (double t = firstSample; t < budget.hopper_fill + budget.hopper_flow + 1e-9; t += sampleEvery) {
    advance(world, t, result, budget.cpu_limit);
    times.push_back(world.time());
    masses.push_back(heldMass());
  }
  result.metrics.emplace_back("discharge_rate", -slope(times, masses));
  finish(result, world, start);
  return result;
}

}  // namespace demlink::study
