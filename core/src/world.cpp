#include "demlink/core/world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "demlink/core/contact/contact_law_registry.hpp"
#include "demlink/core/contact/contact_stage.hpp"
#include "demlink/core/base/input_bounds.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/unit_quaternion.hpp"
#include "demlink/core/step/integrator.hpp"
#include "demlink/core/step/frame_motion.hpp"
#include "demlink/core/parallel/parallel_loops.hpp"
#include "demlink/core/walls/mesh_rebuild_check.hpp"

namespace demlink::core {
namespace {

constexpr const char* kDeformablesNeedAnInertialFrame =
    "deformable bodies in a moving frame are not supported yet (their nodes feel no fictitious forces); use an "
    "inertial frame";

}  // namespace

World::World(SimulationSettings settings, std::string settingsField)
    : settings_(std::move(settings)), settings_field_(std::move(settingsField)), state_(settings_) {
  settings_.validate(settings_field_);
}

std::size_t World::addBondRule(BondRule rule, const std::string& fieldPrefix) {
  if (initialized_) throw InputError(fieldPrefix, rule.name, "parallel bonds must be declared before initialize()");
  rule.properties.validate(fieldPrefix);
  requireHalfOpenRange(fieldPrefix + ".fraction", rule.fraction, 0.0, 1.0);
  for (std::size_t k = 0; k < rule.materials.size(); ++k) {
    if (rule.materials[k] >= materials_.size()) {
      throw InputError(fieldPrefix + ".materials[" + std::to_string(k) + "]", std::to_string(rule.materials[k]),
                       "no such material");
    }
  }
  if (rule.region) rule.placement.resolve(walls_.meshes.size(), fieldPrefix + ".region");
  return bonds_.addRule(std::move(rule));
}

void World::setFrameMotion(const FrameMotion& motion) {
  motion.validate("frame");
  requireNoClumpsInRotatingFrame(motion, "frame");
  requireNoDeformablesInMovingFrame(motion, "frame");
  state_.setFrame(motion);
  if (initialized_) selectStepStages();
}

void World::requireNoClumpsInRotatingFrame(const FrameMotion& motion, const std::string& fieldPrefix) const {
  if (clumps_.templates.empty()) return;
  if (!motion.angular_velocity.isZero(0.0) || !motion.angular_acceleration.isZero(0.0)) {
    throw InputError(fieldPrefix + ".angular_velocity", "non-zero",
                     "clumps in a rotating frame are not supported yet (their rigid-body kick has no fictitious "
                     "torques); use spheres, or a frame that only translates");
  }
}

void World::requireNoDeformablesInMovingFrame(const FrameMotion& motion, const std::string& fieldPrefix) const {
  if (deformables_.bodies.empty() || motion.isInertial()) return;
  throw InputError(fieldPrefix, "non-inertial", kDeformablesNeedAnInertialFrame);
}

void World::requireBoundedFrameAccelerations() const {
  const FrameMotion& frame = state_.frame;
  const double spin = frame.angular_velocity.squaredNorm();  // |Omega|^2 [rad^2/s^2]
  const double turn = frame.angular_acceleration.norm();     // |alpha| [rad/s^2]
  if (spin == 0.0 && turn == 0.0) return;
  double farthest = 0.0;  // [m] from the frame's origin
  for (const Vec3& x : particles_.position) farthest = std::max(farthest, (x - frame.origin).norm());
  const auto refuse = [&](const std::string& field, const Vec3& value, double acceleration, const char* what) {
    throw InputError(settings_field_ + ".frame." + field,
                     "(" + formatValue(value.x()) + ", " + formatValue(value.y()) + ", " + formatValue(value.z()) + ")",
                     std::string(what) + " at the particle farthest from the frame's origin (" + formatValue(farthest) +
                         " m) would be " + formatValue(acceleration) + " m/s^2; at most " +
                         formatValue(kMaxAcceleration) + " m/s^2");
  };
  if (!(spin * farthest <= kMaxAcceleration)) {
    refuse("angular_velocity", frame.angular_velocity, spin * farthest, "the centrifugal acceleration Omega^2 r");
  }
  if (!(turn * farthest <= kMaxAcceleration)) {
    refuse("angular_acceleration", frame.angular_acceleration, turn * farthest, "the Euler acceleration alpha r");
  }
}

void World::setGravity(const Vec3& gravity) {
  requireBoundedVector("gravity", gravity, kMaxAcceleration, "m/s^2");
  state_.gravity = gravity;
  watchdog_.resetEnergy();
}

std::optional<DomainBounds> World::currentBounds() const {
  if (!settings_.bounds) return std::nullopt;
  return state_.bounds;
}

std::uint32_t World::addMaterial(const Material& material) {
  const std::string& prefix = material.name;  // errors name the material by its name
  material.validate(prefix);
  if (materials_.size() >= kMaxMaterials) {
    throw InputError(prefix, std::to_string(materials_.size() + 1) + " materials",
                     "a world holds at most " + std::to_string(kMaxMaterials) +
                         " materials (the pair table grows with the square of the materials in use)");
  }
  if (findMaterial(material.name)) throw InputError(prefix + ".name", material.name, "material name already used");
  materials_.push_back(material);
  return static_cast<std::uint32_t>(materials_.size() - 1);
}

std::optional<std::uint32_t> World::findMaterial(const std::string& name) const {
  for (std::size_t k = 0; k < materials_.size(); ++k) {
    if (materials_[k].name == name) return static_cast<std::uint32_t>(k);
  }
  return std::nullopt;
}

void World::setPairOverride(std::uint32_t materialA, std::uint32_t materialB, const PairOverride& values,
                            const std::string& fieldPrefix) {
  if (initialized_) {
    throw InputError(fieldPrefix, "(pair override)", "pair overrides must be set before initialize()");
  }
  for (const std::uint32_t m : {materialA, materialB}) {
    if (m >= materials_.size()) throw InputError(fieldPrefix + ".material", std::to_string(m), "no such material");
  }
  values.validate(fieldPrefix);
  for (const PairOverrideEntry& entry : contacts_.overrides) {
    if (std::minmax(entry.material_a, entry.material_b) == std::minmax(materialA, materialB)) {
      throw InputError(fieldPrefix, materials_[materialA].name + " / " + materials_[materialB].name,
                       "this material pair already has an override");
    }
  }
  contacts_.overrides.push_back({materialA, materialB, values});
}

std::uint64_t World::addParticle(const ParticleSpec& spec, const std::string& fieldPrefix) {
  requirePositive(fieldPrefix + ".radius", spec.radius);
  requireBoundedVector(fieldPrefix + ".position", spec.position, kMaxCoordinate, "m");
  requireBoundedVector(fieldPrefix + ".velocity", spec.velocity, kMaxSpeed, "m/s");
  requireBoundedVector(fieldPrefix + ".angular_velocity", spec.angular_velocity, kMaxAngularVelocity, "rad/s");
  if (spec.material >= materials_.size()) {
    throw InputError(fieldPrefix + ".material", std::to_string(spec.material), "no such material");
  }
  coverMaterial(spec.material);
  const std::uint64_t id = state_.next_particle_id++;
  particles_.append(spec, materials_[spec.material].density, id);
  neighbours_.rebuild_pending = true;
  return id;
}

std::size_t World::addPlane(PlaneSpec plane, const std::string& fieldPrefix) {
  requireFiniteVector(fieldPrefix + ".point", plane.point);
  requireFiniteVector(fieldPrefix + ".normal", plane.normal);
  const double length = plane.normal.norm();
  if (!(length > 0.0)) throw InputError(fieldPrefix + ".normal", "(0, 0, 0)", "must be a non-zero vector");
  if (plane.material >= materials_.size()) {
    throw InputError(fieldPrefix + ".material", std::to_string(plane.material), "no such material");
  }
  plane.normal /= length;
  if (plane.rigid) plane.material = rigidTwin(plane.material);
  coverMaterial(plane.material);
  walls_.planes.push_back(PlaneWall{std::move(plane), {}, {}, Vec3::Zero(), Vec3::Zero()});
  neighbours_.rebuild_pending = true;
  if (initialized_) selectStepStages();
  return walls_.planes.size() - 1;
}

std::uint32_t World::addClumpTemplate(ClumpTemplate shape, const std::string& fieldPrefix) {
  if (findClumpTemplate(shape.name())) {
    throw InputError(fieldPrefix + ".name", shape.name(), "clump template name already used");
  }
  clumps_.templates.push_back(std::move(shape));
  if (initialized_) selectStepStages();
  return static_cast<std::uint32_t>(clumps_.templates.size() - 1);
}

std::optional<std::uint32_t> World::findClumpTemplate(const std::string& name) const {
  for (std::size_t k = 0; k < clumps_.templates.size(); ++k) {
    if (clumps_.templates[k].name() == name) return static_cast<std::uint32_t>(k);
  }
  return std::nullopt;
}

std::uint64_t World::addClump(const ClumpSpec& spec, const std::string& fieldPrefix) {
  if (spec.template_index >= clumps_.templates.size()) {
    throw InputError(fieldPrefix + ".clump_template", std::to_string(spec.template_index), "no such clump template");
  }
  if (spec.material >= materials_.size()) {
    throw InputError(fieldPrefix + ".material", std::to_string(spec.material), "no such material");
  }
  requireBoundedVector(fieldPrefix + ".position", spec.position, kMaxCoordinate, "m");
  requireBoundedVector(fieldPrefix + ".velocity", spec.velocity, kMaxSpeed, "m/s");
  requireBoundedVector(fieldPrefix + ".angular_velocity", spec.angular_velocity, kMaxAngularVelocity, "rad/s");
  const Quat orientation = requireUnitQuaternion(fieldPrefix + ".orientation", spec.orientation);
  coverMaterial(spec.material);
  const ClumpTemplate& shape = clumps_.templates[spec.template_index];
  const double density = materials_[spec.material].density;  // [kg/m^3]
  ClumpBody body;
  body.id = state_.next_clump_id++;
  body.template_index = spec.template_index;
  body.mass = density * shape.volume();
  body.inertia = density * shape.principalMomentsPerDensity();
  body.position = spec.position;
  body.velocity = spec.velocity;
  body.orientation = (orientation * shape.principalRotation()).normalized();
  const Mat3 rotation = body.orientation.toRotationMatrix();
  body.angular_momentum = rotation * body.inertia.asDiagonal() * rotation.transpose() * spec.angular_velocity;
  const std::size_t members = shape.bodySpheres().size();
  const double share = body.mass / static_cast<double>(members);
  for (const ClumpSphere& sphere : shape.bodySpheres()) {
    ParticleSpec member;
    member.radius = sphere.radius;
    member.material = spec.material;
    particles_.append(member, density, state_.next_particle_id++);
    const std::size_t slot = particles_.size() - 1;
    particles_.clump_id[slot] = body.id;
    particles_.mass[slot] = share;
    particles_.inv_mass[slot] = 1.0 / body.mass;
    particles_.inv_inertia[slot] = 1.0 / body.inertia.minCoeff();
    body.member_slots.push_back(static_cast<std::uint32_t>(slot));
  }
  placeClumpMembers(body, shape, particles_, true);
  clumps_.bodies.push_back(std::move(body));
  neighbours_.rebuild_pending = true;
  return clumps_.bodies.back().id;
}

std::size_t World::addMesh(MeshBody mesh, const std::string& fieldPrefix) {
  if (mesh.materialIndex() >= materials_.size()) {
    throw InputError(fieldPrefix + ".material", std::to_string(mesh.materialIndex()), "no such material");
  }
  if (mesh.rigid()) mesh.setMaterialIndex(rigidTwin(mesh.materialIndex()));
  coverMaterial(mesh.materialIndex());
  walls_.addMesh(std::move(mesh));
  neighbours_.rebuild_pending = true;
  if (initialized_) selectStepStages();
  return walls_.meshes.size() - 1;
}

std::size_t World::addDeformableBody(std::unique_ptr<DeformableBody> body, const std::string& fieldPrefix) {
  if (!body) throw InputError(fieldPrefix, "null", "no deformable body given");
  if (initialized_) {
    throw InputError(fieldPrefix + ".name", body->name(), "deformable bodies must be added before initialize()");
  }
  if (body->surface().materialIndex() >= materials_.size()) {
    throw InputError(fieldPrefix + ".material", std::to_string(body->surface().materialIndex()), "no such material");
  }
  for (const auto& existing : deformables_.bodies) {
    if (existing->name() == body->name()) {
      throw InputError(fieldPrefix + ".name", body->name(), "deformable body name already used");
    }
  }
  if (state_.frame_moving) {
    throw InputError(fieldPrefix + ".name", body->name(), kDeformablesNeedAnInertialFrame);
  }
  deformables_.bodies.push_back(std::move(body));
  deformables_.near.emplace_back();
  neighbours_.rebuild_pending = true;
  return deformables_.bodies.size() - 1;
}

std::uint32_t World::rigidTwin(std::uint32_t material) {
  if (materials_.at(material).rigid) return material;
  const std::string name = materials_[material].name + " (rigid)";
  if (const std::optional<std::uint32_t> twin = findMaterial(name)) return *twin;
  if (initialized_) throw InputError(name, "(rigid wall)", "rigid walls must be added before initialize()");
  Material twin = materials_[material];
  twin.name = name;
  twin.rigid = true;
  materials_.push_back(std::move(twin));
  return static_cast<std::uint32_t>(materials_.size() - 1);
}

void World::declareFutureParticles(std::uint32_t material, double minRadius, const std::string& fieldPrefix) {
  requirePositive(fieldPrefix + ".radius", minRadius);
  if (material >= materials_.size()) {
    throw InputError(fieldPrefix + ".material", std::to_string(material), "no such material");
  }
  contacts_.future_particles.emplace_back(material, minRadius);
}

void World::advanceClockTo(std::uint64_t stepCount) {
  if (stepCount < state_.step_count) {
    throw std::invalid_argument("World::advanceClockTo: step " + std::to_string(stepCount) + " is behind the clock (" +
                                std::to_string(state_.step_count) + ")");
  }
  state_.step_count = stepCount;
}

void World::initialize() {
  if (materials_.empty()) throw InputError("materials", "[]", "a scene needs at least one material");
  std::vector<double> minRadius(materials_.size(), 0.0);
  double radiusSum = 0.0;
  auto noteRadius = [&](std::uint32_t material, double radius) {
    double& r = minRadius[material];
    r = r > 0.0 ? std::min(r, radius) : radius;
    radiusSum += radius;
  };
  for (std::size_t i = 0; i < particles_.size(); ++i) noteRadius(particles_.material[i], particles_.radius[i]);
  for (const auto& [material, radius] : contacts_.future_particles) noteRadius(material, radius);
  const std::size_t sizedCount = particles_.size() + contacts_.future_particles.size();
  const double meanRadius = sizedCount > 0 ? radiusSum / static_cast<double>(sizedCount) : 0.0;
  if (settings_.contact_model == ContactModel::LinearSpringDashpot && meanRadius <= 0.0 &&
      settings_.linear_normal_stiffness <= 0.0) {
    throw InputError(settings_field_ + ".linear_normal_stiffness", "0",
                     "the linear law needs a stiffness when the scene starts without particles");
  }
  contacts_.reference = {meanRadius, settings_.max_impact_velocity, settings_.linear_normal_stiffness};
  buildPairTable(materialsInUse());
  time_step_.seen_speeds = collectSeenSpeeds();
  time_step_.warnings.clear();
  double impactSpeed = settings_.max_impact_velocity;
  if (!time_step_.seen_speeds.empty() && time_step_.seen_speeds.front().speed > impactSpeed) {
    const SeenSpeed& fastest = time_step_.seen_speeds.front();
    impactSpeed = fastest.speed;
    time_step_.warnings.push_back(settings_field_ + ".max_impact_velocity = " +
                                   formatValue(settings_.max_impact_velocity) + " m/s is below the speed of " +
                                   fastest.what + " (" + formatValue(fastest.speed) +
                                   " m/s); the time step is validated for " + formatValue(impactSpeed) + " m/s");
  }
  time_step_.report = criticalTimeStep(materials_, contacts_.table, settings_.contact_model, settings_.integrator,
                                       minRadius, impactSpeed, settings_.restitution_tolerance);
  for (const auto& body : deformables_.bodies) {
    const double limit = body->criticalTimeStep();
    if (!std::isfinite(limit)) continue;  // an unconditionally stable scheme sets no bound
    time_step_.report.addConstraint({"deformable " + body->name(),
                                     std::string(body->kind()) + " body: " + body->criticalTimeStepReason() +
                                         "; softer springs or heavier nodes relax it",
                                     limit});
  }
  bonds_.addTimeStepLimits(time_step_.report, materials_, minRadius);
  if (settings_.time_step > time_step_.report.limit && !settings_.allow_unsafe_time_step) {
    const TimeStepConstraint& limiting = *std::find_if(
        time_step_.report.constraints.begin(), time_step_.report.constraints.end(),
        [&](const TimeStepConstraint& c) { return c.name == time_step_.report.limited_by; });
    throw InputError(settings_field_ + ".time_step", formatValue(settings_.time_step),
                     "exceeds the critical limit " + formatValue(time_step_.report.limit) + " s (limited by " +
                         limiting.name + ": " + limiting.detail +
                         "); lower it, raise restitution_tolerance, or set allow_unsafe_time_step to accept the "
                         "risk");
  }
  if (settings_.neighbour_skin <= 0.0) {
    double smallest = 0.0;
    for (double r : minRadius) {
      if (r > 0.0) smallest = smallest > 0.0 ? std::min(smallest, r) : r;
    }
    state_.neighbour_skin = smallest > 0.0 ? 0.5 * smallest : 1.0e-3;
  }
  neighbours_.list = NeighbourList(state_.neighbour_skin);
  contacts_.kernel = choosePairKernel(settings_.portable_kernel);
  if (settings_.threads > 1) {
    try {
      pool_ = std::make_unique<ThreadPool>(settings_.threads);
    } catch (const ThreadStartError& error) {
      throw InputError(settings_field_ + ".threads", std::to_string(settings_.threads),
                       std::string(error.what()) + "; lower it");
    }
  }

  requireNoClumpsInRotatingFrame(state_.frame, settings_field_ + ".frame");
  requireNoDeformablesInMovingFrame(state_.frame, settings_field_ + ".frame");
  requireBoundedFrameAccelerations();
  initialized_ = true;
  for (const auto& component : components_.all) component->initialize(*this);
  selectStepStages();
  walls_.updateMeshCollision(time());
  rebuildNeighbours();
  // The initial forces belong to the step count now and weigh nothing in time integrals.
  StepContext initial{settings_.time_step, state_.step_count, pool_.get()};
  initial.force_step = state_.step_count;
  (this->*compute_forces_)(initial);
  gatherClumpForces();
  requireFiniteFirstStep();
  watchdog_.resetEnergy();
}

std::vector<std::uint32_t> World::materialsInUse() const {
  std::vector<char> inUse(materials_.size(), 0);
  for (const std::uint32_t m : particles_.material) inUse[m] = 1;
  for (const auto& entry : contacts_.future_particles) inUse[entry.first] = 1;
  for (const PlaneWall& plane : walls_.planes) inUse[plane.spec.material] = 1;
  for (const MeshBody& mesh : walls_.meshes) inUse[mesh.materialIndex()] = 1;
  for (const auto& body : deformables_.bodies) inUse[body->surface().materialIndex()] = 1;
  for (const PairOverrideEntry& entry : contacts_.overrides) inUse[entry.material_a] = inUse[entry.material_b] = 1;
  std::vector<std::uint32_t> used;
  for (std::uint32_t m = 0; m < inUse.size(); ++m) {
    if (inUse[m] != 0) used.push_back(m);
  }
  return used;
}

void World::buildPairTable(const std::vector<std::uint32_t>& used) {
  contacts_.table = ContactPairTable(materials_, settings_.contact_model, contacts_.reference, contacts_.overrides, used);
  contacts_.rolling = contacts_.table.anyRollingFriction();
  contacts_.cohesion = contacts_.table.anyCohesion();
  selectForceKernel();
}

void World::selectForceKernel() {
  using Kernel = void (World::*)(StepContext&);
  // Index: rolling + 2 cohesion + 4 recording.
  const std::size_t index = (contacts_.rolling ? 1u : 0u) + (contacts_.cohesion ? 2u : 0u) +
                            (recorder_.settings.active() ? 4u : 0u);
  compute_forces_ = visitContactLaw(settings_.contact_model, [index]<class Law>() {
    return [&]<std::size_t... I>(std::index_sequence<I...>) {
      constexpr std::array<Kernel, 8> kernels{
          &World::computeForces<Law, ForcePasses{(I & 1u) != 0, (I & 2u) != 0, (I & 4u) != 0}>...};
      return kernels[index];
    }(std::make_index_sequence<8>{});
  });
}

void World::setContactOutput(const ContactOutputSettings& settings) {
  // The same settings again keep what was recorded (the run driver repeats the request
  // its runner made before initialize()).
  if (settings.every_steps == recorder_.settings.every_steps && settings.mesh_loads == recorder_.settings.mesh_loads) return;
  recorder_.settings = settings;
  recorder_.snapshot = ContactSnapshot{};
  recorder_.mesh_loads.clear();
  if (!initialized_) return;
  selectForceKernel();
  selectStepStages();
}

std::span<const TriangleLoad> World::meshLoads(std::size_t index) const {
  if (index >= recorder_.mesh_loads.size()) return {};
  return recorder_.mesh_loads[index];
}

void World::coverMaterial(std::uint32_t material) {
  if (!initialized_ || contacts_.table.covers(material)) return;
  std::vector<std::uint32_t> used = contacts_.table.usedMaterials();
  used.push_back(material);
  std::sort(used.begin(), used.end());
  const bool rolling = contacts_.rolling;
  const bool cohesion = contacts_.cohesion;
  buildPairTable(used);
  if (rolling != contacts_.rolling || cohesion != contacts_.cohesion) selectStepStages();
}

void World::step() { advance(1); }

void World::advance(std::uint64_t steps) {
  if (!initialized_) initialize();
  // Whatever ends the loop (an exception included), the state it leaves is whole.
  struct PayOwedKick {
    World& world;
    ~PayOwedKick() {
      if (world.stepper_.takeOwedKick()) {
        kick(world.particles_, world.state_.gravity, 0.5 * world.settings_.time_step, world.pool_.get());
      }
    }
  } pay{*this};
  for (std::uint64_t n = 0; n < steps; ++n) stepOnce(n + 1 < steps);
}

void World::stepOnce(bool anotherStepFollows) {
  // The watchdog inspects the step's end after advance_clock: the count is one on then.
  const bool endUnobserved = anotherStepFollows && !watchdogInspects(state_.step_count + 1);
  StepContext context =
      stepper_.beginStep(settings_.time_step, state_.step_count, pool_.get(), endUnobserved, state_.frame_moving);
  stepper_.run(context, [this](Stage stage, StepContext& c) { runStage(stage, c); });
}

SceneFeatures World::sceneFeatures() const {
  SceneFeatures f;
  f.meshes = !walls_.meshes.empty();
  f.planes = !walls_.planes.empty();
  f.insert_remove_components = !components_.insert_remove.empty();
  f.observe_components = !components_.observe.empty();
  f.fixed_bounds = settings_.bounds && !settings_.bounds->growing;
  f.growing_bounds = settings_.bounds && settings_.bounds->growing;
  f.velocity_verlet = settings_.integrator == IntegratorKind::VelocityVerlet;
  f.frame_moving = state_.frame_moving;
  f.clumps = !clumps_.templates.empty();
  f.rolling = contacts_.rolling;
  f.deformables = !deformables_.bodies.empty();
  f.watchdog = settings_.watchdog.every_steps > 0;
  f.cohesion = contacts_.cohesion;
  f.contact_recording = recorder_.settings.active();
  f.parallel_bonds = bonds_.hasRules();
  return f;
}

void World::selectStepStages() { stepper_.select(sceneFeatures()); }

void World::runStage(Stage stage, StepContext& context) {
  switch (stage) {
    case Stage::kMeshMotion: return moveMeshes(context);
    case Stage::kInsertRemove: return runComponents(Stage::kInsertRemove);
    case Stage::kBoundsRemoval:
    case Stage::kGrowingBounds: return removeOutsideBounds();
    case Stage::kVelocityVerlet: return firstKickAndDrift(context);
    case Stage::kExplicitEuler: return explicitEulerUpdate(context);
    case Stage::kMovingFrame: return advanceFrame(context);
    case Stage::kClumpRigidBodies: {
      // The kick stage moved the members as spheres; their bodies overwrite them.
      const bool verlet = settings_.integrator == IntegratorKind::VelocityVerlet;
      return integrateClumps(verlet ? 0.5 * context.dt : context.dt, context.dt, !verlet);
    }
    case Stage::kDeformableMotion: return moveDeformables(context);
    case Stage::kDeformableForces: return finishDeformables(context);
    case Stage::kNeighbourList: return updateNeighbours(context);
    case Stage::kForces: return (this->*compute_forces_)(context);
    case Stage::kParallelBonds: return bonds_.step(context.pool, walls_.meshes, time(), particles_, context.dt, context.force_step);
    case Stage::kClumpForceSum: return gatherClumpForces();
    case Stage::kSecondHalfKick: return secondHalfKick(context);
    case Stage::kClumpHalfKick: return integrateClumps(0.5 * context.dt, 0.0, false);
    case Stage::kAdvanceClock: ++state_.step_count; return;
    case Stage::kObserve: return runComponents(Stage::kObserve);
    case Stage::kWatchdog: return runWatchdog();
    case Stage::kParticleContacts:
    case Stage::kPlaneContacts:
    case Stage::kMeshContacts:
    case Stage::kDeformableContacts:
    case Stage::kRollingResistance:
    case Stage::kCohesion:
    case Stage::kContactRecording: return;  // passes inside kForces, never selected as calls
  }
}

void World::moveMeshes(StepContext& context) {
  const double dt = context.dt;
  // Forces of this step are evaluated at the end of the step.
  if (walls_.updateMeshCollision(static_cast<double>(context.step + 1) * dt)) neighbours_.rebuild_pending = true;
  for (std::size_t m = 0; m < walls_.meshes.size(); ++m) {
    MeshBody& mesh = walls_.meshes[m];
    if (!mesh.linearVelocity().isZero(0.0) || !mesh.angularVelocity().isZero(0.0)) {
      mesh.advance(dt);
      watchdog_.noteEnergyFed();
    }
  }
}

void World::moveDeformables(StepContext& context) {
  for (const auto& body : deformables_.bodies) {
    body->beginStep(context.dt, state_.gravity);
    context.mesh_moved_far =
        context.mesh_moved_far || body->surface().maxDisplacementSinceMark() > 0.5 * neighbours_.list.skin();
  }
}

void World::finishDeformables(const StepContext& context) {
  for (const auto& body : deformables_.bodies) {
    const std::uint64_t brokenBefore = body->brokenCount();
    body->endStep(context.dt, state_.gravity);
    // A tear may have deactivated triangles: the next step's near lists leave them out.
    if (body->brokenCount() != brokenBefore) neighbours_.rebuild_pending = true;
  }
}

void World::firstKickAndDrift(StepContext& context) {
  const double dt = context.dt;
  // In a kick-deferrable scene nothing reads or adds to force and torque between this
  // kick and the force stage (stages velocity_verlet, neighbour_list, forces), so the
  // kick clears them and the pair loop need not: one pass over the force columns less.
  const ForcesAfterKick after =
      stepper_.kickDeferrable() && !state_.frame_moving ? ForcesAfterKick::kCleared : ForcesAfterKick::kKept;
  switch (stepper_.takeFirstKick()) {
    case FirstKick::kDoneInForces:
      // The last step's pair loop ran it (computeForces) and cleared force and torque.
      context.forces_cleared = true;
      return;
    case FirstKick::kTwiceAndDrift:
      kickTwiceAndDrift(particles_, state_.gravity, 0.5 * dt, dt, context.pool, after);
      break;
    case FirstKick::kHalfAndDrift:
      if (state_.frame_moving) {
        frameKickAndDrift(particles_, state_.gravity, state_.frame, 0.5 * dt, dt, context.pool);
      } else {
        kickAndDrift(particles_, state_.gravity, 0.5 * dt, dt, context.pool, after);
      }
      break;
  }
  context.forces_cleared = after == ForcesAfterKick::kCleared;
}

void World::explicitEulerUpdate(const StepContext& context) {
  if (state_.frame_moving) {
    frameExplicitEulerStep(particles_, state_.gravity, state_.frame, context.dt, context.pool);
  } else {
    explicitEulerStep(particles_, state_.gravity, context.dt, context.pool);
  }
}

void World::advanceFrame(const StepContext& context) {
  // A constant angular acceleration turns the frame ever faster: Omega(t_n+1) for the second half kick.
  state_.frame.angular_velocity += state_.frame.angular_acceleration * context.dt;
}

void World::updateNeighbours(const StepContext& context) {
  if (neighbours_.rebuild_pending || context.mesh_moved_far || neighbourListsStale(context.pool)) rebuildNeighbours();
}

bool World::neighbourListsStale(ThreadPool* pool) const {
  // Deformable-surface near lists assume that no particle moved more than skin/2 (and
  // the surface no more than skin/2): the classic rule. Pairs and planes need only their
  // relative motion (rebuild_guard.hpp), rigid meshes the particles' motion seen from
  // each mesh (mesh_rebuild_check.hpp).
  if (!deformables_.bodies.empty()) return neighbours_.list.needsRebuild(particles_.position, pool);
  const std::span<const Vec3> built = neighbours_.list.builtPositions();
  if (neighbours_.guard.stale(built, particles_.position, pool)) return true;
  return !walls_.meshes.empty() && meshNearListsStale(walls_.meshes, walls_.mesh_colliding, built, particles_.position,
                                                      particles_.radius, neighbours_.list.skin(), pool);
}

void World::armRebuildGuard() {
  const std::span<const Vec3> built = neighbours_.list.builtPositions();
  neighbours_.guard.arm(built, particles_.radius, neighbours_.list.skin());
  for (const PlaneWall& wall : walls_.planes) {
    neighbours_.guard.addPlane(wall.spec.point, wall.spec.normal, wall.near_slots, built, particles_.radius);
  }
}

void World::secondHalfKick(const StepContext& context) {
  if (!stepper_.takeSecondKick(context)) return;  // owed, or paid in the pair loop
  if (state_.frame_moving) {
    frameKick(particles_, state_.gravity, state_.frame, 0.5 * context.dt, context.pool);
  } else {
    kick(particles_, state_.gravity, 0.5 * context.dt, context.pool);
  }
}

template <class Law, ForcePasses kPasses>
void World::computeForces(StepContext& context) {
  const double dt = context.dt;
  ParticleArrays& p = particles_;
  PairLoopPartition& parts = partition_;
  // Contact records this evaluation? (Only the recording instantiation asks.)
  bool snapshot = false;
  if constexpr (kPasses.recording) {
    const std::uint64_t every = recorder_.settings.every_steps;
    snapshot = every > 0 && (context.force_weight == 0.0 || context.force_step % every == 0);
    recorder_.part_records.resize(parts.chunks());
    for (auto& records : recorder_.part_records) records.clear();
    if (snapshot) {
      recorder_.snapshot.contacts.clear();
      recorder_.snapshot.step = context.force_step;
      recorder_.snapshot.valid = true;
    }
    if (recorder_.settings.mesh_loads) {
      recorder_.mesh_loads.resize(walls_.meshes.size());
      for (std::size_t m = 0; m < walls_.meshes.size(); ++m) {
        recorder_.mesh_loads[m].resize(walls_.meshes[m].triangles().size());
        for (TriangleLoad& load : recorder_.mesh_loads[m]) {
          load.force.setZero();
          load.normal_force = load.tangential_force = 0.0;
        }
      }
    }
  }
  auto chunkRecords = [&](std::uint32_t chunk) -> std::vector<ContactRecord>* {
    return snapshot ? &recorder_.part_records[chunk] : nullptr;
  };
  auto recording = [&](ContactKind kind, std::size_t index, std::vector<TriangleLoad>* loads) {
    ContactRecording r;
    r.contacts = snapshot ? &recorder_.snapshot.contacts : nullptr;
    r.loads = loads;
    r.dt = context.force_weight;
    r.kind = kind;
    r.index = index;
    return r;
  };
  // Pair chunks as PairLoopPartition::run schedules them (each odd chunk after its even
  // neighbours); each chunk then adds the plane and mesh contacts of its own rows, which
  // no chunk running beside it touches (while they are in its thread's cache, and without
  // a loop of their own; the passes of stage forces in stage_table.hpp). A particle near
  // two walls adds their forces in wall order; each plane's load is the chunks' sums in
  // chunk order, and each mesh gets the chunks' surface loads in chunk order, i.e. in its
  // near list's order (ascending slots), whoever ran them. Recording keeps list order:
  // the walls run after all pairs then. Deformable surfaces run after the loop.
  ThreadPool* pool = pool_.get();
  const bool clear = !std::exchange(context.forces_cleared, false);
  const auto pairRows = contacts_.kernel == PairKernel::kAvx2Fma ? &particleContactRowsAvx2Fma<Law, kPasses>
                                                             : &particleContactRows<Law, kPasses>;
  const std::uint32_t chunks = parts.chunks();
  const bool wallsInChunks = !kPasses.recording;
  // Per wall: one load per chunk, and the last for the slots after the listed rows.
  const std::size_t loadsPerWall = std::size_t{chunks} + 1;
  walls_.plane_loads.assign(walls_.planes.size() * loadsPerWall, PlaneLoad{});
  if (walls_.contact_chunks.size() < walls_.meshes.size() * loadsPerWall) {
    walls_.contact_chunks.resize(walls_.meshes.size() * loadsPerWall);
  }
  const auto wallContacts = [&](std::size_t load, std::size_t begin, std::size_t end) {
    for (std::size_t w = 0; w < walls_.planes.size(); ++w) {
      walls_.plane_loads[w * loadsPerWall + load] = planeContactSlots<Law, kPasses>(
          p, walls_.planes[w], contacts_.table, dt, begin, end, recording(ContactKind::kPlane, w, nullptr));
    }
    if constexpr (!kPasses.recording) {
      for (std::size_t m = 0; m < walls_.meshes.size(); ++m) {
        MeshContactChunk& part = walls_.contact_chunks[m * loadsPerWall + load];
        part.loads.clear();
        if (walls_.mesh_colliding[m] == 0) continue;
        meshContactSlots<Law, kPasses>(p, walls_.meshes[m], walls_.mesh_near[m], contacts_.table, dt, begin, end, part);
      }
    }
  };
  // The next step's first kick in the chunks (Stepper::beginStep): only where every force
  // of a row is final when its chunks are, i.e. the chunks add the walls too, every slot
  // has rows, and no deformable surface adds forces after the loop. (Scenes with meshes
  // owe no kicks today: stages mesh_motion and mesh_contacts forbid it, stage_table.cpp.)
  const bool kickInChunks = context.next_kick_in_forces && wallsInChunks && chunks > 0 &&
                            parts.rowEnd(chunks - 1) == p.size() && deformables_.bodies.empty();
  const Vec3 gravity = state_.gravity;
  parts.run(pool, [&](std::uint32_t chunk) {
    const ChunkForces out = parts.start(chunk, p.force, p.torque, clear);
    pairRows(p, neighbours_.list, contacts_.table, dt, parts.rowBegin(chunk), parts.rowEnd(chunk), out, chunkRecords(chunk));
    if (wallsInChunks) wallContacts(chunk, parts.rowBegin(chunk), parts.rowEnd(chunk));
    if (kickInChunks) {
      const auto [begin, end] = parts.rowsDoneAfter(chunk);
      kickTwiceAndDriftRows(p, gravity, 0.5 * dt, dt, begin, end);
    }
  });
  stepper_.setKickDoneInForces(kickInChunks);
  // Slots the list has no rows for yet (none between rebuilds, kept for safety).
  const std::size_t listed = std::min(p.size(), chunks > 0 ? parts.rowEnd(chunks - 1) : 0);
  std::fill(p.force.begin() + static_cast<std::ptrdiff_t>(listed), p.force.end(), Vec3::Zero());
  std::fill(p.torque.begin() + static_cast<std::ptrdiff_t>(listed), p.torque.end(), Vec3::Zero());
  if (snapshot) {
    for (const auto& records : recorder_.part_records) {
      recorder_.snapshot.contacts.insert(recorder_.snapshot.contacts.end(), records.begin(), records.end());
    }
  }
  wallContacts(chunks, wallsInChunks ? listed : 0, p.size());
  for (std::size_t w = 0; w < walls_.planes.size(); ++w) {
    PlaneWall& wall = walls_.planes[w];
    wall.force.setZero();
    wall.torque.setZero();
    for (std::size_t c = 0; c < loadsPerWall; ++c) {
      wall.force += walls_.plane_loads[w * loadsPerWall + c].force;
      wall.torque += walls_.plane_loads[w * loadsPerWall + c].torque;
    }
  }
  for (std::size_t m = 0; m < walls_.meshes.size(); ++m) {
    MeshBody& mesh = walls_.meshes[m];
    mesh.clearWrench();
    if (walls_.mesh_colliding[m] == 0) continue;
    if constexpr (kPasses.recording) {
      std::vector<TriangleLoad>* loads = recorder_.settings.mesh_loads ? &recorder_.mesh_loads[m] : nullptr;
      meshContactForces<Law, kPasses>(p, mesh, walls_.mesh_near[m], contacts_.table, dt, walls_.contact_scratch,
                                      recording(ContactKind::kMesh, m, loads));
    } else {
      for (std::size_t c = 0; c < loadsPerWall; ++c) addSurfaceLoads(mesh, walls_.contact_chunks[m * loadsPerWall + c]);
    }
  }
  for (std::size_t d = 0; d < deformables_.bodies.size(); ++d) {
    DeformableSurface& surface = deformables_.bodies[d]->surface();
    surface.clearForces();
    meshContactForces<Law, kPasses>(p, surface, deformables_.near[d], contacts_.table, dt, walls_.contact_scratch,
                                    recording(ContactKind::kDeformable, d, nullptr));
  }
}

void World::integrateClumps(double kickStep, double driftStep, bool driftFirst) {
  for (ClumpBody& body : clumps_.bodies) {
    if (driftFirst) driftClump(body, driftStep);
    // A frame that only translates is a gravity shift (rotating frames are refused with clumps).
    kickClump(body, state_.gravity - state_.frame.linear_acceleration, kickStep);
    if (!driftFirst && driftStep > 0.0) driftClump(body, driftStep);
    placeClumpMembers(body, clumps_.templates[body.template_index], particles_, driftStep > 0.0);
  }
}

void World::gatherClumpForces() {
  for (ClumpBody& body : clumps_.bodies) core::gatherClumpForces(body, particles_);
}

void World::removeFlaggedWithClumps(RemovalTally& tally) {
  std::vector<char>& flags = clumps_.removal_flags;
  for (const ClumpBody& body : clumps_.bodies) {
    const bool any = std::any_of(body.member_slots.begin(), body.member_slots.end(),
                                 [&](std::uint32_t slot) { return flags[slot] != 0; });
    if (!any) continue;
    for (const std::uint32_t slot : body.member_slots) flags[slot] = 1;
    ++tally.count;
    tally.mass += body.mass;
  }
  std::erase_if(clumps_.bodies, [&](const ClumpBody& body) { return flags[body.member_slots.front()] != 0; });
  std::vector<std::uint32_t> keep;
  keep.reserve(particles_.size());
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (flags[i] == 0) {
      keep.push_back(static_cast<std::uint32_t>(i));
    } else if (particles_.clump_id[i] == 0) {
      ++tally.count;
      tally.mass += particles_.mass[i];
    }
  }
  applySlotMapping(keep);
}

void World::removeOutsideBounds() {
  const DomainBounds& b = *settings_.bounds;
  if (b.growing) {
    // One pass: remove beyond the limit, and grow the box around the spheres kept.
    Vec3 lower = state_.bounds.lower;
    Vec3 upper = state_.bounds.upper;
    removeParticlesIf(
        [&](std::size_t i) {
          const Vec3& x = particles_.position[i];
          if (!((x.array() >= b.limit_lower.array()).all() && (x.array() <= b.limit_upper.array()).all())) {
            return true;
          }
          const double r = particles_.radius[i];
          lower = lower.cwiseMin(x - Vec3::Constant(r));
          upper = upper.cwiseMax(x + Vec3::Constant(r));
          return false;
        },
        state_.removed_at_bounds);
    state_.bounds.lower = lower.cwiseMax(b.limit_lower);
    state_.bounds.upper = upper.cwiseMin(b.limit_upper);
    return;
  }
  removeParticlesIf(
      [&](std::size_t i) {
        const Vec3& x = particles_.position[i];
        return !((x.array() >= b.lower.array()).all() && (x.array() <= b.upper.array()).all());
      },
      state_.removed_at_bounds);
}

WorldComponent& World::addComponent(std::unique_ptr<WorldComponent> component) {
  if (!component) throw InputError("component", "null", "no component given");
  for (const auto& existing : components_.all) {
    if (existing->name() == component->name()) {
      throw InputError(component->name() + ".name", component->name(), "component name already used");
    }
  }
  WorldComponent& added = *component;
  components_.all.push_back(std::move(component));
  if (added.stages() & stageBit(Stage::kInsertRemove)) components_.insert_remove.push_back(&added);
  if (added.stages() & stageBit(Stage::kObserve)) components_.observe.push_back(&added);
  if (initialized_) {
    added.initialize(*this);
    selectStepStages();
  }
  return added;
}

void World::runComponents(Stage stage) {
  if (stage == Stage::kInsertRemove) {
    for (WorldComponent* component : components_.insert_remove) component->insertAndRemove(*this);
  } else {
    for (WorldComponent* component : components_.observe) component->observe(*this);
  }
}

void World::applySlotMapping(const std::vector<std::uint32_t>& oldSlotOfNew) {
  const std::size_t before = particles_.size();
  particles_.permute(oldSlotOfNew);
  std::vector<std::uint32_t> newOfCurrent(before, kRemovedSlot);
  for (std::size_t k = 0; k < oldSlotOfNew.size(); ++k) newOfCurrent[oldSlotOfNew[k]] = static_cast<std::uint32_t>(k);
  for (ClumpBody& body : clumps_.bodies) {
    for (std::uint32_t& slot : body.member_slots) slot = newOfCurrent[slot];
  }
  bonds_.remapSlots(newOfCurrent);
  if (neighbours_.pending_new_slot_of_old.empty()) {
    neighbours_.pending_new_slot_of_old = std::move(newOfCurrent);
  } else {
    for (std::uint32_t& slot : neighbours_.pending_new_slot_of_old) {
      if (slot != kRemovedSlot) slot = newOfCurrent[slot];
    }
  }
  neighbours_.rebuild_pending = true;
}

void World::rebuildNeighbours() {
  const std::uint32_t every = settings_.sort_every_builds;
  if (every > 0 && neighbours_.list.buildCount() % every == 0 && particles_.size() > 1) {
    // Cell-ordered slots keep neighbours close in memory for the force loop.
    CellGrid grid;
    grid.build(particles_.position, particles_.radius, neighbours_.list.skin());
    applySlotMapping(grid.spatialOrder(particles_.position));
  }
  neighbours_.list.build(particles_, neighbours_.pending_new_slot_of_old, pool_.get(), !clumps_.bodies.empty());
  partition_.plan(neighbours_.list.offsets(), neighbours_.list.partners());
  for (PlaneWall& wall : walls_.planes) wall.buildNearList(particles_, neighbours_.list.skin(), neighbours_.pending_new_slot_of_old);
  for (std::size_t m = 0; m < walls_.meshes.size(); ++m) {
    if (walls_.mesh_colliding[m] != 0) {
      walls_.mesh_near[m].build(particles_, walls_.meshes[m], neighbours_.list.grid(), neighbours_.list.skin(), neighbours_.pending_new_slot_of_old);
    } else {
      walls_.mesh_near[m] = MeshNearList{};  // not in contact: no candidates, springs released
    }
    walls_.meshes[m].markNeighbourBuild();
  }
  for (std::size_t d = 0; d < deformables_.bodies.size(); ++d) {
    const DeformableSurface& surface = deformables_.bodies[d]->surface();
    deformables_.near[d].build(particles_, surface.worldVertices(), surface.triangles(), surface.active(),
                              neighbours_.list.grid(), neighbours_.list.skin(), neighbours_.pending_new_slot_of_old);
    deformables_.bodies[d]->surface().markNeighbourBuild();
  }
  neighbours_.pending_new_slot_of_old.clear();
  neighbours_.rebuild_pending = false;
  armRebuildGuard();
}

std::vector<std::string> World::activeStages() const {
  const auto componentsIn = [](const std::vector<WorldComponent*>& list, std::vector<std::string>& names) {
    for (const WorldComponent* c : list) names.push_back(std::string(c->kind()) + ":" + c->name());
  };
  std::vector<std::string> names;
  for (const Stage stage : selectStages(sceneFeatures())) {
    if (stage == Stage::kDeformableMotion || stage == Stage::kDeformableForces) {
      for (const auto& body : deformables_.bodies) names.push_back(std::string(body->kind()) + ":" + body->name());
    } else if (stage == Stage::kInsertRemove) {
      componentsIn(components_.insert_remove, names);
    } else if (stage == Stage::kObserve) {
      componentsIn(components_.observe, names);
    } else if (stage == Stage::kParticleContacts) {
      names.push_back("particle_contacts:" + std::string(toString(settings_.contact_model)));
    } else {
      names.emplace_back(stageInfo(stage).name);
    }
  }
  return names;
}

double World::kineticEnergy() const {
  double energy = 0.0;
  for (const ClumpBody& body : clumps_.bodies) energy += body.kineticEnergy();
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (particles_.clump_id[i] != 0) continue;  // counted with its body
    energy += particles_.sphereKineticEnergy(i);
  }
  return energy;
}

double World::totalMass() const {
  if (clumps_.bodies.empty()) return std::accumulate(particles_.mass.begin(), particles_.mass.end(), 0.0);
  double mass = 0.0;
  for (const ClumpBody& body : clumps_.bodies) mass += body.mass;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (particles_.clump_id[i] == 0) mass += particles_.mass[i];
  }
  return mass;
}

}  // namespace demlink::core

namespace demlink::core {

std::vector<SeenSpeed> World::collectSeenSpeeds() const {
  std::vector<SeenSpeed> speeds;
  const ParticleArrays& p = particles_;
  std::size_t fastest = p.size();
  double fastestSpeed = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    // Surface speed: translation plus spin at the rim.
    const double speed = p.velocity[i].norm() + p.angular_velocity[i].norm() * p.radius[i];
    if (speed > fastestSpeed) {
      fastestSpeed = speed;
      fastest = i;
    }
  }
  if (fastest < p.size()) speeds.push_back({"particle " + std::to_string(p.id[fastest]), fastestSpeed});
  for (const auto& component : components_.all) {
    if (const std::optional<double> speed = component->largestSpeed(*this); speed && *speed > 0.0) {
      speeds.push_back({std::string(component->kind()) + " " + component->name(), *speed});
    }
  }
  double reach = 0.0;  // farthest particle or mesh point from the frame's origin [m]
  for (std::size_t i = 0; i < p.size(); ++i) {
    reach = std::max(reach, (p.position[i] - state_.frame.origin).norm() + p.radius[i]);
  }
  for (const MeshBody& mesh : walls_.meshes) {
    reach = std::max(reach, (mesh.position() - state_.frame.origin).norm() + mesh.boundingRadius());
    const double moving = mesh.linearVelocity().norm() + mesh.angularVelocity().norm() * mesh.boundingRadius();
    const double speed = std::max(moving, mesh.speedLimit());
    if (speed > 0.0) {
      speeds.push_back({"mesh " + mesh.name() + (mesh.speedLimit() >= moving ? " (declared max_speed)" : ""),
                        speed});
    }
  }
  // Walls and meshes at rest in a rotating frame sweep past the inertial particles.
  const double spin = state_.frame.angular_velocity.norm() * reach;
  if (spin > 0.0) speeds.push_back({"the frame's rotation (at " + formatValue(reach) + " m from its origin)", spin});
  std::stable_sort(speeds.begin(), speeds.end(), [](const SeenSpeed& a, const SeenSpeed& b) { return a.speed > b.speed; });
  return speeds;
}

void World::requireFiniteFirstStep() const {
  // The first step adds (F/m + g + fictitious) dt to every velocity; its kinetic
  // energy m v^2 must stay finite. Each term is checked alone so the error names
  // the input that overflows (finite inputs such as gravity 1e308 still do).
  const double dt = settings_.time_step;
  const ParticleArrays& p = particles_;
  double maxMass = 0.0;
  double maxSpeed = 0.0;
  double reach = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    maxMass = std::max(maxMass, p.mass[i]);
    maxSpeed = std::max(maxSpeed, p.velocity[i].norm());
    reach = std::max(reach, (p.position[i] - state_.frame.origin).norm());
  }
  if (p.size() == 0) return;
  auto overflows = [&](double speedChange) {
    const double v = maxSpeed + speedChange;
    return !std::isfinite(speedChange) || !std::isfinite(maxMass * v * v) || !std::isfinite(reach + v * dt);
  };
  const std::string reason = "makes the first step's kinetic energy or positions overflow (not finite)";
  if (overflows(0.0)) throw InputError("particles.velocity", formatValue(maxSpeed) + " m/s", reason);
  if (overflows(state_.gravity.norm() * dt)) {
    throw InputError(settings_field_ + ".gravity", formatValue(state_.gravity.norm()) + " m/s^2", reason);
  }
  const FrameMotion& f = state_.frame;
  const double omega = f.angular_velocity.norm();
  if (overflows(f.linear_acceleration.norm() * dt)) {
    throw InputError(settings_field_ + ".frame.linear_acceleration", formatValue(f.linear_acceleration.norm()), reason);
  }
  if (overflows((omega * omega * reach + 2.0 * omega * maxSpeed) * dt)) {
    throw InputError(settings_field_ + ".frame.angular_velocity", formatValue(omega) + " rad/s", reason);
  }
  if (overflows(f.angular_acceleration.norm() * reach * dt)) {
    throw InputError(settings_field_ + ".frame.angular_acceleration", formatValue(f.angular_acceleration.norm()),
                     reason);
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!std::isfinite(p.force[i].squaredNorm() * p.inv_mass[i] * dt) || overflows(p.force[i].norm() * p.inv_mass[i] * dt)) {
      throw InputError("particle " + std::to_string(p.id[i]) + ".position", formatValue(p.position[i].x()),
                       "its initial contact force overflows (an overlap too deep for the stiffness)");
    }
  }
}

namespace {

/// One chunk's share of a watchdog reading (World::watch): sums, and the first extreme with
/// the slots it came from. Shares are combined in chunk order, and the chunks depend on the
/// particle count alone (parallel_loops.hpp), so a reading does not depend on the thread count and
/// names the particle a serial scan would.
struct WatchShare {
  static constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::size_t non_finite = kNone;
  double max_speed = 0.0;
  std::size_t fastest = kNone;
  double potential = 0.0;  ///< gravitational [J]
  double elastic = 0.0;    ///< [J]
  double cohesion = 0.0;   ///< [J]
  double max_overlap_fraction = 0.0;
  std::size_t deep_a = kNone;  ///< the deepest pair's slots
  std::size_t deep_b = kNone;

  /// Adds the share of the chunk after this one's.
  void add(const WatchShare& next) {
    if (non_finite == kNone) non_finite = next.non_finite;
    if (next.max_speed > max_speed) {
      max_speed = next.max_speed;
      fastest = next.fastest;
    }
    potential += next.potential;
    elastic += next.elastic;
    cohesion += next.cohesion;
    if (next.max_overlap_fraction > max_overlap_fraction) {
      max_overlap_fraction = next.max_overlap_fraction;
      deep_a = next.deep_a;
      deep_b = next.deep_b;
    }
  }
};

/// body(share, begin, end) for the chunks of [0, n) over `pool`, then their shares combined.
template <class Body>
WatchShare watchChunks(ThreadPool* pool, std::size_t n, const Body& body) {
  const std::uint32_t chunks = chunkCount(n);
  std::vector<WatchShare> shares(chunks);
  parallelParts(pool, chunks, [&](std::uint32_t c) {
    body(shares[c], chunkBegin(n, chunks, c), chunkBegin(n, chunks, c + 1));
  });
  for (std::uint32_t c = 1; c < chunks; ++c) shares[0].add(shares[c]);
  return shares[0];
}

}  // namespace

template <class Law>
void World::measureContacts(WatchdogReading& reading) const {
  const ParticleArrays& p = particles_;
  const auto offsets = neighbours_.list.offsets();
  const auto partners = neighbours_.list.partners();
  // Adds a contact's energies to `share`; true when it is the deepest so far.
  auto note = [](WatchShare& share, double overlap, double rA, double rB, const ContactPairParams& params) {
    if (overlap <= 0.0) return false;
    const double rStar = rB > 0.0 ? rA * rB / (rA + rB) : rA;
    const ContactStiffness k = Law::stiffness(params, rStar, overlap);
    share.elastic += k.normal_elastic_force * overlap / (Law::kForceExponent + 1.0);
    share.cohesion += cohesionEnergy(params.cohesion_energy_density, rA, rB, overlap);
    const double fraction = overlap / (rB > 0.0 ? std::min(rA, rB) : rA);
    if (!(fraction > share.max_overlap_fraction)) return false;
    share.max_overlap_fraction = fraction;
    return true;
  };
  const std::size_t rows = offsets.empty() ? 0 : offsets.size() - 1;
  WatchShare all = watchChunks(pool_.get(), rows, [&](WatchShare& share, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
        const std::uint32_t j = partners[k];
        const double overlap = p.radius[i] + p.radius[j] - (p.position[j] - p.position[i]).norm();
        if (note(share, overlap, p.radius[i], p.radius[j], contacts_.table(p.material[i], p.material[j]))) {
          share.deep_a = i;
          share.deep_b = j;
        }
      }
    }
  });
  reading.elastic_energy += all.elastic;
  reading.cohesion_energy += all.cohesion;
  reading.max_overlap_fraction = all.max_overlap_fraction;
  if (all.deep_a != WatchShare::kNone) {
    reading.deepest = "particles " + std::to_string(p.id[all.deep_a]) + " and " + std::to_string(p.id[all.deep_b]);
  }
  // Planes after all pairs, as a serial scan: a plane contact is the deepest only when deeper.
  for (std::size_t w = 0; w < walls_.planes.size(); ++w) {
    const PlaneWall& wall = walls_.planes[w];
    WatchShare share;
    share.max_overlap_fraction = reading.max_overlap_fraction;
    for (const std::uint32_t i : wall.near_slots) {
      const double overlap = p.radius[i] - (p.position[i] - wall.spec.point).dot(wall.spec.normal);
      if (note(share, overlap, p.radius[i], 0.0, contacts_.table(p.material[i], wall.spec.material))) {
        reading.deepest = "particle " + std::to_string(p.id[i]) + " on plane " + wall.spec.name;
      }
    }
    reading.elastic_energy += share.elastic;
    reading.cohesion_energy += share.cohesion;
    reading.max_overlap_fraction = share.max_overlap_fraction;
  }
}

std::string World::nonFiniteState() const {
  const ParticleArrays& p = particles_;
  const WatchShare scan = watchChunks(pool_.get(), p.size(), [&](WatchShare& share, std::size_t begin,
                                                                std::size_t end) {
    for (std::size_t i = begin; i < end && share.non_finite == WatchShare::kNone; ++i) {
      const double sum = p.position[i].sum() + p.velocity[i].sum() + p.angular_velocity[i].sum() + p.force[i].sum();
      if (!std::isfinite(sum)) share.non_finite = i;
    }
  });
  if (scan.non_finite != WatchShare::kNone) {
    return "particle " + std::to_string(p.id[scan.non_finite]) + " (position, velocity, spin or force)";
  }
  for (const MeshBody& mesh : walls_.meshes) {
    if (!std::isfinite(mesh.position().sum() + mesh.orientation().coeffs().sum() + mesh.linearVelocity().sum() +
                       mesh.angularVelocity().sum())) {
      return "mesh " + mesh.name() + " (pose or velocity)";
    }
  }
  for (const auto& body : deformables_.bodies) {
    for (const Vec3& x : body->surface().positions()) {
      if (!std::isfinite(x.sum())) return std::string(body->kind()) + " body " + body->name() + " (node positions)";
    }
  }
  return {};
}

WatchdogReading World::watch() {
  WatchdogReading r;
  r.non_finite = nonFiniteState();
  if (!r.non_finite.empty()) return r;
  const ParticleArrays& p = particles_;
  const Vec3 gravity = state_.gravity;
  const WatchShare motion = watchChunks(pool_.get(), p.size(), [&](WatchShare& share, std::size_t begin,
                                                                  std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const double speed = p.velocity[i].norm();
      if (speed > share.max_speed) {
        share.max_speed = speed;
        share.fastest = i;
      }
      share.potential -= p.mass[i] * gravity.dot(p.position[i]);
    }
  });
  r.max_speed = motion.max_speed;
  if (motion.fastest != WatchShare::kNone) r.fastest = "particle " + std::to_string(p.id[motion.fastest]);
  for (const MeshBody& mesh : walls_.meshes) {
    const double speed = mesh.linearVelocity().norm() + mesh.angularVelocity().norm() * mesh.boundingRadius();
    if (speed > r.max_speed) {
      r.max_speed = speed;
      r.fastest = "mesh " + mesh.name();
    }
  }
  visitContactLaw(settings_.contact_model, [&]<class Law>() { measureContacts<Law>(r); });
  r.elastic_energy += bonds_.strainEnergy(particles_);
  r.kinetic_energy = kineticEnergy();
  r.total_energy = r.kinetic_energy + motion.potential + r.elastic_energy + r.cohesion_energy;
  // Sources, moving meshes and a moving frame feed energy in: no energy check then.
  // Mesh contacts' elastic energy and deformable bodies' energy are not measured, so scenes
  // with meshes or deformable bodies are not checked either.
  const bool energyFed = watchdog_.takeEnergyFed();
  r.energy_checked = components_.insert_remove.empty() && !state_.frame_moving && !energyFed && walls_.meshes.empty() &&
                     deformables_.bodies.empty();
  if (energyFed) watchdog_.resetEnergy();
  return r;
}

bool World::watchdogInspects(std::uint64_t stepCount) const {
  const std::uint64_t every = settings_.watchdog.every_steps;
  return every > 0 && stepCount % every == 0;
}

void World::runWatchdog() {
  if (!watchdogInspects(state_.step_count)) return;
  const WatchdogReading reading = watch();
  if (std::optional<SimulationFault> fault =
          watchdog_.assess(reading, settings_.watchdog, time_step_.report.impact_speed, state_.step_count)) {
    throw *fault;
  }
}

std::vector<std::string> World::warnings() const {
  std::vector<std::string> all = time_step_.warnings;
  all.insert(all.end(), watchdog_.warnings().begin(), watchdog_.warnings().end());
  return all;
}

}  // namespace demlink::core
