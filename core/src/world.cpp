#include "demlink/core/world.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include "demlink/core/contact/contact_law_registry.hpp"
#include "demlink/core/contact/contact_stage.hpp"
#include "demlink/core/input_bounds.hpp"
#include "demlink/core/input_error.hpp"
#include "demlink/core/unit_quaternion.hpp"
#include "demlink/core/step/integrator.hpp"
#include "demlink/core/step/frame_motion.hpp"
#include "demlink/core/step/parallel.hpp"
#include "demlink/core/step/stage_sampling.hpp"

namespace demlink::core {
namespace {

constexpr const char* kDeformablesNeedAnInertialFrame =
    "deformable bodies in a moving frame are not supported yet (their nodes feel no fictitious forces); use an "
    "inertial frame";

void requireFiniteVector(const std::string& field, const Vec3& v) {
  for (int k = 0; k < 3; ++k) requireFinite(field + "[" + std::to_string(k) + "]", v[k]);
}

}  // namespace

World::World(SimulationSettings settings, std::string settingsField)
    : settings_(std::move(settings)), settings_field_(std::move(settingsField)), state_(settings_) {
  settings_.validate(settings_field_);
}

void World::setFrameMotion(const FrameMotion& motion) {
  motion.validate("frame");
  requireNoClumpsInRotatingFrame(motion, "frame");
  requireNoDeformablesInMovingFrame(motion, "frame");
  state_.setFrame(motion);
  if (initialized_) selectStepStages();
}

void World::requireNoClumpsInRotatingFrame(const FrameMotion& motion, const std::string& fieldPrefix) const {
  if (clump_templates_.empty()) return;
  if (!motion.angular_velocity.isZero(0.0) || !motion.angular_acceleration.isZero(0.0)) {
    throw InputError(fieldPrefix + ".angular_velocity", "non-zero",
                     "clumps in a rotating frame are not supported yet (their rigid-body kick has no fictitious "
                     "torques); use spheres, or a frame that only translates");
  }
}

void World::requireNoDeformablesInMovingFrame(const FrameMotion& motion, const std::string& fieldPrefix) const {
  if (deformables_.empty() || motion.isInertial()) return;
  throw InputError(fieldPrefix, "non-inertial", kDeformablesNeedAnInertialFrame);
}

void World::requireBoundedFrameAccelerations() const {
  const FrameMotion& frame = state_.frame;
  const double spin = frame.angular_velocity.squaredNorm();  // |Omega|^2 [rad^2/s^2]
  const double turn = frame.angular_acceleration.norm();     // |alpha| [rad/s^2]
  if (spin == 0.0 && turn == 0.0) return;
  double farthest = 0.0;  // [m] from the room's origin
  for (const Vec3& x : particles_.position) farthest = std::max(farthest, (x - frame.origin).norm());
  const auto refuse = [&](const std::string& field, const Vec3& value, double acceleration, const char* what) {
    throw InputError(settings_field_ + ".frame." + field,
                     "(" + formatValue(value.x()) + ", " + formatValue(value.y()) + ", " + formatValue(value.z()) + ")",
                     std::string(what) + " at the particle farthest from the room's origin (" + formatValue(farthest) +
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
  for (const PairOverrideEntry& entry : pair_overrides_) {
    if (std::minmax(entry.material_a, entry.material_b) == std::minmax(materialA, materialB)) {
      throw InputError(fieldPrefix, materials_[materialA].name + " / " + materials_[materialB].name,
                       "this material pair already has an override");
    }
  }
  pair_overrides_.push_back({materialA, materialB, values});
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
  rebuild_pending_ = true;
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
  planes_.push_back(PlaneWall{std::move(plane), {}, {}, Vec3::Zero(), Vec3::Zero()});
  rebuild_pending_ = true;
  if (initialized_) selectStepStages();
  return planes_.size() - 1;
}

std::uint32_t World::addClumpTemplate(ClumpTemplate shape, const std::string& fieldPrefix) {
  if (findClumpTemplate(shape.name())) {
    throw InputError(fieldPrefix + ".name", shape.name(), "clump template name already used");
  }
  clump_templates_.push_back(std::move(shape));
  if (initialized_) selectStepStages();
  return static_cast<std::uint32_t>(clump_templates_.size() - 1);
}

std::optional<std::uint32_t> World::findClumpTemplate(const std::string& name) const {
  for (std::size_t k = 0; k < clump_templates_.size(); ++k) {
    if (clump_templates_[k].name() == name) return static_cast<std::uint32_t>(k);
  }
  return std::nullopt;
}

std::uint64_t World::addClump(const ClumpSpec& spec, const std::string& fieldPrefix) {
  if (spec.template_index >= clump_templates_.size()) {
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
  const ClumpTemplate& shape = clump_templates_[spec.template_index];
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
  clumps_.push_back(std::move(body));
  rebuild_pending_ = true;
  return clumps_.back().id;
}

std::size_t World::addMesh(MeshBody mesh, const std::string& fieldPrefix) {
  if (mesh.materialIndex() >= materials_.size()) {
    throw InputError(fieldPrefix + ".material", std::to_string(mesh.materialIndex()), "no such material");
  }
  if (mesh.rigid()) mesh.setMaterialIndex(rigidTwin(mesh.materialIndex()));
  coverMaterial(mesh.materialIndex());
  meshes_.push_back(std::move(mesh));
  mesh_near_.emplace_back();
  mesh_colliding_.push_back(0);
  rebuild_pending_ = true;
  if (initialized_) selectStepStages();
  return meshes_.size() - 1;
}

std::size_t World::addDeformableBody(std::unique_ptr<DeformableBody> body, const std::string& fieldPrefix) {
  if (!body) throw InputError(fieldPrefix, "null", "no deformable body given");
  if (initialized_) {
    throw InputError(fieldPrefix + ".name", body->name(), "deformable bodies must be added before initialize()");
  }
  if (body->surface().materialIndex() >= materials_.size()) {
    throw InputError(fieldPrefix + ".material", std::to_string(body->surface().materialIndex()), "no such material");
  }
  for (const auto& existing : deformables_) {
    if (existing->name() == body->name()) {
      throw InputError(fieldPrefix + ".name", body->name(), "deformable body name already used");
    }
  }
  if (state_.frame_moving) {
    throw InputError(fieldPrefix + ".name", body->name(), kDeformablesNeedAnInertialFrame);
  }
  deformables_.push_back(std::move(body));
  deformable_near_.emplace_back();
  rebuild_pending_ = true;
  return deformables_.size() - 1;
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
  future_particles_.emplace_back(material, minRadius);
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
  for (const auto& [material, radius] : future_particles_) noteRadius(material, radius);
  const std::size_t sizedCount = particles_.size() + future_particles_.size();
  const double meanRadius = sizedCount > 0 ? radiusSum / static_cast<double>(sizedCount) : 0.0;
  if (settings_.contact_model == ContactModel::LinearSpringDashpot && meanRadius <= 0.0 &&
      settings_.linear_normal_stiffness <= 0.0) {
    throw InputError(settings_field_ + ".linear_normal_stiffness", "0",
                     "the linear law needs a stiffness when the scene starts without particles");
  }
  pair_reference_ = {meanRadius, settings_.max_impact_velocity, settings_.linear_normal_stiffness};
  buildPairTable(materialsInUse());
  seen_speeds_ = collectSeenSpeeds();
  initialize_warnings_.clear();
  double impactSpeed = settings_.max_impact_velocity;
  if (!seen_speeds_.empty() && seen_speeds_.front().speed > impactSpeed) {
    const SeenSpeed& fastest = seen_speeds_.front();
    impactSpeed = fastest.speed;
    initialize_warnings_.push_back(settings_field_ + ".max_impact_velocity = " +
                                   formatValue(settings_.max_impact_velocity) + " m/s is below the speed of " +
                                   fastest.what + " (" + formatValue(fastest.speed) +
                                   " m/s); the time step is validated for " + formatValue(impactSpeed) + " m/s");
  }
  time_step_report_ = criticalTimeStep(materials_, pair_table_, settings_.contact_model, settings_.integrator,
                                       minRadius, impactSpeed, settings_.restitution_tolerance);
  for (const auto& body : deformables_) {
    const double limit = body->criticalTimeStep();
    if (!std::isfinite(limit)) continue;  // an unconditionally stable scheme sets no bound
    time_step_report_.addConstraint({"deformable " + body->name(),
                                     std::string(body->kind()) + " body: " + body->criticalTimeStepReason() +
                                         "; softer springs or heavier nodes relax it",
                                     limit});
  }
  if (settings_.time_step > time_step_report_.limit && !settings_.allow_unsafe_time_step) {
    const TimeStepConstraint& limiting = *std::find_if(
        time_step_report_.constraints.begin(), time_step_report_.constraints.end(),
        [&](const TimeStepConstraint& c) { return c.name == time_step_report_.limited_by; });
    throw InputError(settings_field_ + ".time_step", formatValue(settings_.time_step),
                     "exceeds the critical limit " + formatValue(time_step_report_.limit) + " s (limited by " +
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
  neighbours_ = NeighbourList(state_.neighbour_skin);
  pair_kernel_ = choosePairKernel(settings_.portable_kernel);
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
  for (const auto& component : components_) component->initialize(*this);
  selectStepStages();
  updateMeshCollision(time());
  rebuildNeighbours();
  force_step_ = state_.step_count;
  force_weight_ = 0.0;
  (this->*compute_forces_)();
  gatherClumpForces();
  requireFiniteFirstStep();
  watchdog_.resetEnergy();
}

std::vector<std::uint32_t> World::materialsInUse() const {
  std::vector<char> inUse(materials_.size(), 0);
  for (const std::uint32_t m : particles_.material) inUse[m] = 1;
  for (const auto& entry : future_particles_) inUse[entry.first] = 1;
  for (const PlaneWall& plane : planes_) inUse[plane.spec.material] = 1;
  for (const MeshBody& mesh : meshes_) inUse[mesh.materialIndex()] = 1;
  for (const auto& body : deformables_) inUse[body->surface().materialIndex()] = 1;
  for (const PairOverrideEntry& entry : pair_overrides_) inUse[entry.material_a] = inUse[entry.material_b] = 1;
  std::vector<std::uint32_t> used;
  for (std::uint32_t m = 0; m < inUse.size(); ++m) {
    if (inUse[m] != 0) used.push_back(m);
  }
  return used;
}

void World::buildPairTable(const std::vector<std::uint32_t>& used) {
  pair_table_ = ContactPairTable(materials_, settings_.contact_model, pair_reference_, pair_overrides_, used);
  rolling_active_ = pair_table_.anyRollingFriction();
  cohesion_active_ = pair_table_.anyCohesion();
  selectForceKernel();
}

void World::selectForceKernel() {
  using Kernel = void (World::*)();
  // Index: rolling + 2 cohesion + 4 recording.
  const std::size_t index = (rolling_active_ ? 1u : 0u) + (cohesion_active_ ? 2u : 0u) +
                            (contact_output_.active() ? 4u : 0u);
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
  if (settings.every_steps == contact_output_.every_steps && settings.mesh_loads == contact_output_.mesh_loads) return;
  contact_output_ = settings;
  contact_snapshot_ = ContactSnapshot{};
  mesh_loads_.clear();
  if (!initialized_) return;
  selectForceKernel();
  selectStepStages();
}

std::span<const TriangleLoad> World::meshLoads(std::size_t index) const {
  if (index >= mesh_loads_.size()) return {};
  return mesh_loads_[index];
}

void World::coverMaterial(std::uint32_t material) {
  if (!initialized_ || pair_table_.covers(material)) return;
  std::vector<std::uint32_t> used = pair_table_.usedMaterials();
  used.push_back(material);
  std::sort(used.begin(), used.end());
  const bool rolling = rolling_active_;
  const bool cohesion = cohesion_active_;
  buildPairTable(used);
  if (rolling != rolling_active_ || cohesion != cohesion_active_) selectStepStages();
}

void World::step() { advance(1); }

void World::advance(std::uint64_t steps) {
  if (!initialized_) initialize();
  // Whatever ends the loop (an exception included), the state it leaves is whole.
  struct PayOwedKick {
    World& world;
    ~PayOwedKick() {
      if (world.half_kick_owed_) world.payOwedHalfKick();
    }
  } pay{*this};
  for (std::uint64_t n = 0; n < steps; ++n) stepOnce(kick_deferrable_ && n + 1 < steps);
}

void World::payOwedHalfKick() {
  half_kick_owed_ = false;
  kick(particles_, state_.gravity, 0.5 * settings_.time_step, pool_.get());
}

void World::stepOnce(bool mayOweKick) {
  forces_cleared_ = false;
  StepContext context{settings_.time_step, state_.step_count, pool_.get()};
  // The watchdog inspects the step's end after advance_clock: the count is one on then.
  context.may_owe_kick = mayOweKick && !watchdogInspects(state_.step_count + 1);
  // A step that would owe its second half kick to the next one (secondHalfKick) may as
  // well pay it, with the next step's first kick and drift, inside its pair loop: each
  // chunk then kicks the rows it has just finished while they are in its thread's cache,
  // instead of a pass of its own over every column at the next step's start. The same
  // additions in the same order, so the same bits (Determinism tests).
  next_kick_in_forces_ = context.may_owe_kick && !state_.frame_moving;
  force_step_ = state_.step_count + 1;  // the forces of a step belong to its end
  force_weight_ = settings_.time_step;
  const std::uint64_t weight = stage_timing_ ? stageTimingWeight(state_.step_count) : 0;
  if (weight == 0) {
    for (const Stage stage : step_stages_) runStage(stage, context);
    return;
  }
  using Clock = std::chrono::steady_clock;
  Clock::time_point last = Clock::now();
  for (const Stage stage : step_stages_) {
    runStage(stage, context);
    const Clock::time_point now = Clock::now();
    stage_seconds_[static_cast<std::size_t>(stage)] +=
        static_cast<double>(weight) * std::chrono::duration<double>(now - last).count();
    last = now;
  }
}

SceneFeatures World::sceneFeatures() const {
  SceneFeatures f;
  f.meshes = !meshes_.empty();
  f.planes = !planes_.empty();
  f.insert_remove_components = !insert_remove_components_.empty();
  f.observe_components = !observe_components_.empty();
  f.fixed_bounds = settings_.bounds && !settings_.bounds->growing;
  f.growing_bounds = settings_.bounds && settings_.bounds->growing;
  f.velocity_verlet = settings_.integrator == IntegratorKind::VelocityVerlet;
  f.frame_moving = state_.frame_moving;
  f.clumps = !clump_templates_.empty();
  f.rolling = rolling_active_;
  f.deformables = !deformables_.empty();
  f.watchdog = settings_.watchdog.every_steps > 0;
  f.cohesion = cohesion_active_;
  f.contact_recording = contact_output_.active();
  return f;
}

void World::selectStepStages() {
  step_stages_.clear();
  for (const Stage stage : selectStages(sceneFeatures())) {
    if (!stageInfo(stage).pass) step_stages_.push_back(stage);
  }
  // Between a step's second half kick and the next step's first kick only these stages
  // may run for the kick to be owed: none of them reads a velocity or a force (the
  // watchdog does, at the steps it inspects: secondHalfKick pays before those). Every
  // other stage (components, clumps, meshes, deformables, bounds, a moving frame)
  // reads or changes them there.
  kick_deferrable_ = std::all_of(step_stages_.begin(), step_stages_.end(), [](Stage stage) {
    return stage == Stage::kVelocityVerlet || stage == Stage::kNeighbourList || stage == Stage::kForces ||
           stage == Stage::kSecondHalfKick || stage == Stage::kAdvanceClock || stage == Stage::kWatchdog;
  });
}

void World::runStage(Stage stage, StepContext& context) {
  switch (stage) {
    case Stage::kMeshMotion: return moveMeshes(context);
    case Stage::kInsertRemove: return runComponents(kStageInsertRemove);
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
    case Stage::kForces: return (this->*compute_forces_)();
    case Stage::kClumpForceSum: return gatherClumpForces();
    case Stage::kSecondHalfKick: return secondHalfKick(context);
    case Stage::kClumpHalfKick: return integrateClumps(0.5 * context.dt, 0.0, false);
    case Stage::kAdvanceClock: ++state_.step_count; return;
    case Stage::kObserve: return runComponents(kStageObserve);
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
  if (updateMeshCollision(static_cast<double>(context.step + 1) * dt)) rebuild_pending_ = true;
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    MeshBody& mesh = meshes_[m];
    if (!mesh.linearVelocity().isZero(0.0) || !mesh.angularVelocity().isZero(0.0)) {
      mesh.advance(dt);
      energy_fed_ = true;
    }
    const bool farEnough = mesh.maxDisplacementSinceMark() > 0.5 * neighbours_.skin();
    context.mesh_moved_far = context.mesh_moved_far || (mesh_colliding_[m] != 0 && farEnough);
  }
}

void World::moveDeformables(StepContext& context) {
  for (const auto& body : deformables_) {
    body->beginStep(context.dt, state_.gravity);
    context.mesh_moved_far =
        context.mesh_moved_far || body->surface().maxDisplacementSinceMark() > 0.5 * neighbours_.skin();
  }
}

void World::finishDeformables(const StepContext& context) {
  for (const auto& body : deformables_) {
    const std::uint64_t brokenBefore = body->brokenCount();
    body->endStep(context.dt, state_.gravity);
    // A tear may have deactivated triangles: the next step's near lists leave them out.
    if (body->brokenCount() != brokenBefore) rebuild_pending_ = true;
  }
}

void World::firstKickAndDrift(const StepContext& context) {
  const double dt = context.dt;
  // In a kick-deferrable scene nothing reads or adds to force and torque between this
  // kick and the force stage (stages velocity_verlet, neighbour_list, forces), so the
  // kick clears them and the pair loop need not (a clearing pass of 2.4 MB at 50,000
  // particles). A step that throws in between leaves them zero; stepOnce resets the flag.
  const ForcesAfterKick after =
      kick_deferrable_ && !state_.frame_moving ? ForcesAfterKick::kCleared : ForcesAfterKick::kKept;
  if (first_kick_done_) {
    // The last step's pair loop ran it (computeForces) and cleared force and torque.
    first_kick_done_ = false;
    ++fused_kicks_;
    forces_cleared_ = true;
    return;
  }
  if (half_kick_owed_) {
    half_kick_owed_ = false;
    ++fused_kicks_;
    kickTwiceAndDrift(particles_, state_.gravity, 0.5 * dt, dt, context.pool, after);
  } else if (state_.frame_moving) {
    frameKickAndDrift(particles_, state_.gravity, state_.frame, 0.5 * dt, dt, context.pool);
  } else {
    kickAndDrift(particles_, state_.gravity, 0.5 * dt, dt, context.pool, after);
  }
  forces_cleared_ = after == ForcesAfterKick::kCleared;
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
  if (rebuild_pending_ || context.mesh_moved_far || neighbourListsStale(context.pool)) rebuildNeighbours();
}

bool World::neighbourListsStale(ThreadPool* pool) const {
  // Mesh and deformable-surface near lists assume that no particle moved more than
  // skin/2 (and the surface no more than skin/2): the classic rule. Pairs and planes
  // alone need only their relative motion (rebuild_guard.hpp).
  if (!meshes_.empty() || !deformables_.empty()) return neighbours_.needsRebuild(particles_.position, pool);
  return rebuild_guard_.stale(neighbours_.builtPositions(), particles_.position, pool);
}

void World::armRebuildGuard() {
  const std::span<const Vec3> built = neighbours_.builtPositions();
  rebuild_guard_.arm(built, particles_.radius, neighbours_.skin());
  for (const PlaneWall& wall : planes_) {
    rebuild_guard_.addPlane(wall.spec.point, wall.spec.normal, wall.near_slots, built, particles_.radius);
  }
}

void World::secondHalfKick(const StepContext& context) {
  if (first_kick_done_) return;  // paid in the pair loop, with the next step's first kick
  if (context.may_owe_kick) {
    half_kick_owed_ = true;
    return;
  }
  if (state_.frame_moving) {
    frameKick(particles_, state_.gravity, state_.frame, 0.5 * context.dt, context.pool);
  } else {
    kick(particles_, state_.gravity, 0.5 * context.dt, context.pool);
  }
}

template <class Law, ForcePasses kPasses>
void World::computeForces() {
  const double dt = settings_.time_step;
  ParticleArrays& p = particles_;
  PairLoopPartition& parts = partition_;
  // Contact records this evaluation? (Only the recording instantiation asks.)
  bool snapshot = false;
  if constexpr (kPasses.recording) {
    const std::uint64_t every = contact_output_.every_steps;
    snapshot = every > 0 && (force_weight_ == 0.0 || force_step_ % every == 0);
    part_records_.resize(parts.chunks());
    for (auto& records : part_records_) records.clear();
    if (snapshot) {
      contact_snapshot_.contacts.clear();
      contact_snapshot_.step = force_step_;
      contact_snapshot_.valid = true;
    }
    if (contact_output_.mesh_loads) {
      mesh_loads_.resize(meshes_.size());
      for (std::size_t m = 0; m < meshes_.size(); ++m) {
        mesh_loads_[m].resize(meshes_[m].triangles().size());
        for (TriangleLoad& load : mesh_loads_[m]) {
          load.force.setZero();
          load.normal_force = load.tangential_force = 0.0;
        }
      }
    }
  }
  auto chunkRecords = [&](std::uint32_t chunk) -> std::vector<ContactRecord>* {
    return snapshot ? &part_records_[chunk] : nullptr;
  };
  auto recording = [&](ContactKind kind, std::size_t index, std::vector<TriangleLoad>* loads) {
    ContactRecording r;
    r.contacts = snapshot ? &contact_snapshot_.contacts : nullptr;
    r.loads = loads;
    r.dt = force_weight_;
    r.kind = kind;
    r.index = index;
    return r;
  };
  // Pair chunks as PairLoopPartition::run schedules them (each odd chunk after its even
  // neighbours); each chunk then adds the plane contacts of its own rows, which no chunk
  // running beside it touches (while they are in its thread's cache, and without a loop
  // of their own); then meshes (the passes of stage forces in stage_table.hpp). A particle near two planes
  // adds their forces in plane order; each wall's load is the chunks' sums in chunk order,
  // whoever ran them. Recording keeps list order: the planes run after all pairs then.
  ThreadPool* pool = pool_.get();
  const bool clear = !std::exchange(forces_cleared_, false);
  const auto pairRows = pair_kernel_ == PairKernel::kAvx2Fma ? &particleContactRowsAvx2Fma<Law, kPasses>
                                                             : &particleContactRows<Law, kPasses>;
  const std::uint32_t chunks = parts.chunks();
  const bool planesInChunks = !kPasses.recording;
  // Per plane: one load per chunk, and the last for the slots after the listed rows.
  const std::size_t loadsPerPlane = std::size_t{chunks} + 1;
  plane_loads_.assign(planes_.size() * loadsPerPlane, PlaneLoad{});
  const auto planeContacts = [&](std::size_t load, std::size_t begin, std::size_t end) {
    for (std::size_t w = 0; w < planes_.size(); ++w) {
      plane_loads_[w * loadsPerPlane + load] = planeContactSlots<Law, kPasses>(
          p, planes_[w], pair_table_, dt, begin, end, recording(ContactKind::kPlane, w, nullptr));
    }
  };
  // The next step's first kick in the chunks (stepOnce; consumed here, so no evaluation
  // outside a step sees it): only where every force of a row is final when its chunks
  // are, i.e. the chunks add the planes too, every slot has rows, and no mesh or
  // deformable surface adds forces after the loop.
  const bool kickInChunks = std::exchange(next_kick_in_forces_, false) && planesInChunks && chunks > 0 &&
                            parts.rowEnd(chunks - 1) == p.size() && meshes_.empty() && deformables_.empty();
  const Vec3 gravity = state_.gravity;
  parts.run(pool, [&](std::uint32_t chunk) {
    const ChunkForces out = parts.start(chunk, p.force, p.torque, clear);
    pairRows(p, neighbours_, pair_table_, dt, parts.rowBegin(chunk), parts.rowEnd(chunk), out, chunkRecords(chunk));
    if (planesInChunks) planeContacts(chunk, parts.rowBegin(chunk), parts.rowEnd(chunk));
    if (kickInChunks) {
      const auto [begin, end] = parts.rowsDoneAfter(chunk);
      kickTwiceAndDriftRows(p, gravity, 0.5 * dt, dt, begin, end);
    }
  });
  first_kick_done_ = kickInChunks;
  // Slots the list has no rows for yet (none between rebuilds, kept for safety).
  const std::size_t listed = std::min(p.size(), chunks > 0 ? parts.rowEnd(chunks - 1) : 0);
  std::fill(p.force.begin() + static_cast<std::ptrdiff_t>(listed), p.force.end(), Vec3::Zero());
  std::fill(p.torque.begin() + static_cast<std::ptrdiff_t>(listed), p.torque.end(), Vec3::Zero());
  if (snapshot) {
    for (const auto& records : part_records_) {
      contact_snapshot_.contacts.insert(contact_snapshot_.contacts.end(), records.begin(), records.end());
    }
  }
  planeContacts(chunks, planesInChunks ? listed : 0, p.size());
  for (std::size_t w = 0; w < planes_.size(); ++w) {
    PlaneWall& wall = planes_[w];
    wall.force.setZero();
    wall.torque.setZero();
    for (std::size_t c = 0; c < loadsPerPlane; ++c) {
      wall.force += plane_loads_[w * loadsPerPlane + c].force;
      wall.torque += plane_loads_[w * loadsPerPlane + c].torque;
    }
  }
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    meshes_[m].clearWrench();
    if (mesh_colliding_[m] == 0) continue;
    std::vector<TriangleLoad>* loads = kPasses.recording && contact_output_.mesh_loads ? &mesh_loads_[m] : nullptr;
    meshContactForces<Law, kPasses>(p, meshes_[m], mesh_near_[m], pair_table_, dt, mesh_contacts_scratch_,
                                    recording(ContactKind::kMesh, m, loads));
  }
  for (std::size_t d = 0; d < deformables_.size(); ++d) {
    DeformableSurface& surface = deformables_[d]->surface();
    surface.clearForces();
    meshContactForces<Law, kPasses>(p, surface, deformable_near_[d], pair_table_, dt, mesh_contacts_scratch_,
                                    recording(ContactKind::kDeformable, d, nullptr));
  }
}

void World::integrateClumps(double kickStep, double driftStep, bool driftFirst) {
  for (ClumpBody& body : clumps_) {
    if (driftFirst) driftClump(body, driftStep);
    // A frame that only translates is a gravity shift (rotating frames are refused with clumps).
    kickClump(body, state_.gravity - state_.frame.linear_acceleration, kickStep);
    if (!driftFirst && driftStep > 0.0) driftClump(body, driftStep);
    placeClumpMembers(body, clump_templates_[body.template_index], particles_, driftStep > 0.0);
  }
}

void World::gatherClumpForces() {
  for (ClumpBody& body : clumps_) core::gatherClumpForces(body, particles_);
}

void World::removeFlaggedWithClumps(RemovalTally& tally) {
  std::vector<char>& flags = removal_flags_;
  for (const ClumpBody& body : clumps_) {
    const bool any = std::any_of(body.member_slots.begin(), body.member_slots.end(),
                                 [&](std::uint32_t slot) { return flags[slot] != 0; });
    if (!any) continue;
    for (const std::uint32_t slot : body.member_slots) flags[slot] = 1;
    ++tally.count;
    tally.mass += body.mass;
  }
  std::erase_if(clumps_, [&](const ClumpBody& body) { return flags[body.member_slots.front()] != 0; });
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

bool World::updateMeshCollision(double time) {
  bool changed = false;
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const char colliding = meshes_[m].collidesAt(time) ? 1 : 0;
    changed = changed || colliding != mesh_colliding_[m];
    mesh_colliding_[m] = colliding;
  }
  return changed;
}

WorldComponent& World::addComponent(std::unique_ptr<WorldComponent> component) {
  if (!component) throw InputError("component", "null", "no component given");
  for (const auto& existing : components_) {
    if (existing->name() == component->name()) {
      throw InputError(component->name() + ".name", component->name(), "component name already used");
    }
  }
  WorldComponent& added = *component;
  components_.push_back(std::move(component));
  if (added.stages() & kStageInsertRemove) insert_remove_components_.push_back(&added);
  if (added.stages() & kStageObserve) observe_components_.push_back(&added);
  if (initialized_) {
    added.initialize(*this);
    selectStepStages();
  }
  return added;
}

void World::runComponents(std::uint32_t stage) {
  if (stage == kStageInsertRemove) {
    for (WorldComponent* component : insert_remove_components_) component->insertAndRemove(*this);
  } else {
    for (WorldComponent* component : observe_components_) component->observe(*this);
  }
}

void World::applySlotMapping(const std::vector<std::uint32_t>& oldSlotOfNew) {
  const std::size_t before = particles_.size();
  particles_.permute(oldSlotOfNew);
  std::vector<std::uint32_t> newOfCurrent(before, kRemovedSlot);
  for (std::size_t k = 0; k < oldSlotOfNew.size(); ++k) newOfCurrent[oldSlotOfNew[k]] = static_cast<std::uint32_t>(k);
  for (ClumpBody& body : clumps_) {
    for (std::uint32_t& slot : body.member_slots) slot = newOfCurrent[slot];
  }
  if (pending_new_slot_of_old_.empty()) {
    pending_new_slot_of_old_ = std::move(newOfCurrent);
  } else {
    for (std::uint32_t& slot : pending_new_slot_of_old_) {
      if (slot != kRemovedSlot) slot = newOfCurrent[slot];
    }
  }
  rebuild_pending_ = true;
}

void World::rebuildNeighbours() {
  const std::uint32_t every = settings_.sort_every_builds;
  if (every > 0 && neighbours_.buildCount() % every == 0 && particles_.size() > 1) {
    // Cell-ordered slots keep neighbours close in memory for the force loop.
    CellGrid grid;
    grid.build(particles_.position, particles_.radius, neighbours_.skin());
    applySlotMapping(grid.spatialOrder(particles_.position));
  }
  neighbours_.build(particles_, pending_new_slot_of_old_, pool_.get(), !clumps_.empty());
  partition_.plan(neighbours_.offsets(), neighbours_.partners());
  for (PlaneWall& wall : planes_) wall.buildNearList(particles_, neighbours_.skin(), pending_new_slot_of_old_);
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    if (mesh_colliding_[m] != 0) {
      mesh_near_[m].build(particles_, meshes_[m], neighbours_.grid(), neighbours_.skin(), pending_new_slot_of_old_);
    } else {
      mesh_near_[m] = MeshNearList{};  // not in contact: no candidates, springs released
    }
    meshes_[m].markNeighbourBuild();
  }
  for (std::size_t d = 0; d < deformables_.size(); ++d) {
    const DeformableSurface& surface = deformables_[d]->surface();
    deformable_near_[d].build(particles_, surface.worldVertices(), surface.triangles(), surface.active(),
                              neighbours_.grid(), neighbours_.skin(), pending_new_slot_of_old_);
    deformables_[d]->surface().markNeighbourBuild();
  }
  pending_new_slot_of_old_.clear();
  rebuild_pending_ = false;
  armRebuildGuard();
}

std::vector<std::string> World::activeStages() const {
  const auto componentsIn = [](const std::vector<WorldComponent*>& list, std::vector<std::string>& names) {
    for (const WorldComponent* c : list) names.push_back(std::string(c->kind()) + ":" + c->name());
  };
  std::vector<std::string> names;
  for (const Stage stage : selectStages(sceneFeatures())) {
    if (stage == Stage::kDeformableMotion || stage == Stage::kDeformableForces) {
      for (const auto& body : deformables_) names.push_back(std::string(body->kind()) + ":" + body->name());
    } else if (stage == Stage::kInsertRemove) {
      componentsIn(insert_remove_components_, names);
    } else if (stage == Stage::kObserve) {
      componentsIn(observe_components_, names);
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
  for (const ClumpBody& body : clumps_) energy += body.kineticEnergy();
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (particles_.clump_id[i] != 0) continue;  // counted with its body
    energy += 0.5 * particles_.mass[i] * particles_.velocity[i].squaredNorm() +
              0.5 / particles_.inv_inertia[i] * particles_.angular_velocity[i].squaredNorm();
  }
  return energy;
}

double World::totalMass() const {
  if (clumps_.empty()) return std::accumulate(particles_.mass.begin(), particles_.mass.end(), 0.0);
  double mass = 0.0;
  for (const ClumpBody& body : clumps_) mass += body.mass;
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
  for (const auto& component : components_) {
    if (const std::optional<double> speed = component->largestSpeed(*this); speed && *speed > 0.0) {
      speeds.push_back({std::string(component->kind()) + " " + component->name(), *speed});
    }
  }
  double reach = 0.0;  // farthest particle or mesh point from the frame's origin [m]
  for (std::size_t i = 0; i < p.size(); ++i) {
    reach = std::max(reach, (p.position[i] - state_.frame.origin).norm() + p.radius[i]);
  }
  for (const MeshBody& mesh : meshes_) {
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
/// particle count alone (parallel.hpp), so a reading does not depend on the thread count and
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
  const auto offsets = neighbours_.offsets();
  const auto partners = neighbours_.partners();
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
        if (note(share, overlap, p.radius[i], p.radius[j], pair_table_(p.material[i], p.material[j]))) {
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
  for (std::size_t w = 0; w < planes_.size(); ++w) {
    const PlaneWall& wall = planes_[w];
    WatchShare share;
    share.max_overlap_fraction = reading.max_overlap_fraction;
    for (const std::uint32_t i : wall.near_slots) {
      const double overlap = p.radius[i] - (p.position[i] - wall.spec.point).dot(wall.spec.normal);
      if (note(share, overlap, p.radius[i], 0.0, pair_table_(p.material[i], wall.spec.material))) {
        reading.deepest = "particle " + std::to_string(p.id[i]) + " on plane " + wall.spec.name;
      }
    }
    reading.elastic_energy += share.elastic;
    reading.cohesion_energy += share.cohesion;
    reading.max_overlap_fraction = share.max_overlap_fraction;
  }
}

WatchdogReading World::watch() {
  WatchdogReading r;
  const ParticleArrays& p = particles_;
  const Vec3 gravity = state_.gravity;
  const WatchShare motion = watchChunks(pool_.get(), p.size(), [&](WatchShare& share, std::size_t begin,
                                                                  std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const double check =
          p.position[i].sum() + p.velocity[i].sum() + p.angular_velocity[i].sum() + p.force[i].sum();
      if (!std::isfinite(check) && share.non_finite == WatchShare::kNone) share.non_finite = i;
      const double speed = p.velocity[i].norm();
      if (speed > share.max_speed) {
        share.max_speed = speed;
        share.fastest = i;
      }
      share.potential -= p.mass[i] * gravity.dot(p.position[i]);
    }
  });
  if (motion.non_finite != WatchShare::kNone) {
    r.non_finite = "particle " + std::to_string(p.id[motion.non_finite]) + " (position, velocity, spin or force)";
  }
  r.max_speed = motion.max_speed;
  if (motion.fastest != WatchShare::kNone) r.fastest = "particle " + std::to_string(p.id[motion.fastest]);
  for (const MeshBody& mesh : meshes_) {
    const double speed = mesh.linearVelocity().norm() + mesh.angularVelocity().norm() * mesh.boundingRadius();
    if (speed > r.max_speed) {
      r.max_speed = speed;
      r.fastest = "mesh " + mesh.name();
    }
  }
  for (const auto& body : deformables_) {
    for (const Vec3& x : body->surface().positions()) {
      if (!std::isfinite(x.sum()) && r.non_finite.empty()) {
        r.non_finite = std::string(body->kind()) + " body " + body->name() + " (node positions)";
      }
    }
  }
  if (!r.non_finite.empty()) return r;
  visitContactLaw(settings_.contact_model, [&]<class Law>() { measureContacts<Law>(r); });
  r.kinetic_energy = kineticEnergy();
  r.total_energy = r.kinetic_energy + motion.potential + r.elastic_energy + r.cohesion_energy;
  // Sources, moving meshes and a moving frame feed energy in: no energy check then.
  // Mesh contacts' elastic energy and deformable bodies' energy are not measured, so scenes
  // with meshes or deformable bodies are not checked either.
  r.energy_checked = insert_remove_components_.empty() && !state_.frame_moving && !energy_fed_ && meshes_.empty() &&
                     deformables_.empty();
  if (energy_fed_) {
    watchdog_.resetEnergy();
    energy_fed_ = false;
  }
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
          watchdog_.assess(reading, settings_.watchdog, time_step_report_.impact_speed, state_.step_count)) {
    throw *fault;
  }
}

std::vector<std::string> World::warnings() const {
  std::vector<std::string> all = initialize_warnings_;
  all.insert(all.end(), watchdog_.warnings().begin(), watchdog_.warnings().end());
  return all;
}

}  // namespace demlink::core
