/// Typed helpers of the C ABI: one declare call per kind and one exchange/read call per
/// exchanged kind, with scalars and fixed-size arrays a Modelica external function can
/// pass directly. The exchange calls follow the client's exchange order (demlink_c.h,
/// "Exchange orders").
#include <array>
#include <climits>
#include <cmath>
#include <sstream>

#include "c_internal.hpp"

namespace demlink::client::c_abi {
namespace {

Vec3 vec(const double* a, const char* what) {
  if (a == nullptr) throw ArgumentError(std::string(what) + " is NULL");
  return {a[0], a[1], a[2]};
}

std::string str(const char* s) { return s != nullptr ? std::string(s) : std::string(); }



/// NaN or negative: "not given" (the server's default).
bool given(double value) { return !std::isnan(value) && value >= 0.0; }

int clampCount(std::uint64_t count) { return static_cast<int>(std::min<std::uint64_t>(count, INT_MAX)); }

int declareComponent(Client& c, std::unique_ptr<Component> component, double interval, int* handle) {
  if (handle == nullptr) throw ArgumentError("component (the handle output) is NULL");
  Session& session = sessionOf(c);
  if (!std::isfinite(interval) || interval < 0.0) {
    throw ArgumentError("communication interval must be >= 0 s, got " + std::to_string(interval));
  }
  component->setCommunicationInterval(interval);
  std::size_t index = 0;
  session.declareOnce(std::move(component), index);
  *handle = static_cast<int>(index);
  return DL_OK;
}

/// Four vectors as twelve reals x y z, x y z, ... (a wrench pair or the reactions).
/// w x y z; NULL: no rotation.
Quat quat(const double* q) { return q != nullptr ? Quat{q[0], q[1], q[2], q[3]} : Quat{}; }

/// A region sensor or sink on an oriented box, fixed or attached to a body.
template <class Region>
int declareOrientedBox(dl_client* client, const char* name, double interval, const double* centre,
                       const double* size, const double* orientation, const char* attachedTo, int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto region = std::make_unique<Region>(str(name));
    region->setBox(vec(centre, "centre"), vec(size, "size"), quat(orientation));
    if (!str(attachedTo).empty()) region->attachTo(attachedTo);
    return declareComponent(c, std::move(region), interval, component);
  });
}

/// A region sensor or sink on a sphere, fixed or attached to a body.
template <class Region>
int declareSphere(dl_client* client, const char* name, double interval, const double* centre, double radius,
                  const char* attachedTo, int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto region = std::make_unique<Region>(str(name));
    region->setSphere(vec(centre, "centre"), radius);
    if (!str(attachedTo).empty()) region->attachTo(attachedTo);
    return declareComponent(c, std::move(region), interval, component);
  });
}

void flatten(const std::array<Vec3, 4>& parts, double* out) {
  for (std::size_t i = 0; i < parts.size(); ++i) {
    out[3 * i] = parts[i].x;
    out[3 * i + 1] = parts[i].y;
    out[3 * i + 2] = parts[i].z;
  }
}

/// Fixed and driven boxes (lo(3) hi(3) each), the driving reference and attachment of a
/// deformable body's declaration.
template <class Message>
void constrain(Message& body, int fixedCount, const double* fixed, int drivenCount, const double* driven,
               const double* reference, const char* attachedTo) {
  const auto regions = [](v1::NodeSet& set, int count, const double* boxes, const char* what) {
    if (count < 0 || (count > 0 && boxes == nullptr)) throw ArgumentError(std::string(what) + ": bad count or NULL");
    for (int k = 0; k < count; ++k) {
      v1::NodeRegion& region = *set.add_regions();
      *region.mutable_lo() = toProto(vec(boxes + 6 * k, what));
      *region.mutable_hi() = toProto(vec(boxes + 6 * k + 3, what));
    }
  };
  regions(*body.mutable_fixed(), fixedCount, fixed, "fixedRegions");
  regions(*body.mutable_driven(), drivenCount, driven, "drivenRegions");
  if (reference != nullptr) *body.mutable_driven_reference() = toProto(vec(reference, "drivenReference"));
  body.set_attached_to(str(attachedTo));
}

template <class T>
T& typed(Client& c, int component, const char* kind) {
  auto* t = dynamic_cast<T*>(&componentOf(c, component));
  if (t == nullptr) {
    throw ArgumentError("component " + std::to_string(component) + " is a " + componentOf(c, component).kind() +
                        ", not a " + kind);
  }
  return *t;
}

/// A due package is sent unless the run's last step has passed (the server then ends it).
bool sendIfDue(Session& session, Component& component) {
  if (session.endStep() != 0 && component.nextSendStep() >= session.endStep()) return false;
  session.send(component);
  return true;
}

/// The one-call send-first order waits for its own answer, which needs every component due
/// at the same step to have sent: another of this client's components still to send would
/// wait forever. Refused instead, naming the order that handles it.
void requireAloneAtItsStep(Session& session, const Component& component) {
  for (std::size_t i = 0; i < session.size(); ++i) {
    const Component& other = session.component(i);
    if (&other == &component || !other.exchanged() || other.awaitingAnswer()) continue;
    if (other.nextSendStep() == component.nextSendStep()) {
      throw StateError("component '" + other.name() + "' of this client is also due at step " +
                       std::to_string(component.nextSendStep()) +
                       ": with several exchanged components use DL_ORDER_SEND_FIRST_SPLIT (two calls per sample) "
                       "or DL_ORDER_RECEIVE_FIRST (dl_set_exchange_order)");
    }
  }
}

/// True when the answer in flight for `component` ends at the next step the world advances
/// to: the nearest step where any component of the simulation is due (Compiled's
/// all_components; this client's own when the server lists none). Only then can the
/// split order's second call wait for it: a component with a longer interval than the
/// fastest one gets its answer while the faster ones step on, and receives it at its next
/// sample's first call instead.
bool answerEndsThisRound(Session& session, const Component& component) {
  const std::uint64_t sent = component.nextSendStep();
  const std::uint64_t start = session.compiled().start_step();
  std::uint64_t next = 0;
  const auto consider = [&](std::uint64_t interval) {
    if (interval == 0) return;
    const std::uint64_t candidate = start + ((sent - start) / interval + 1) * interval;
    if (next == 0 || candidate < next) next = candidate;
  };
  if (session.compiled().all_components_size() > 0) {
    for (const v1::CompiledComponent& c : session.compiled().all_components()) consider(c.interval_steps());
  } else {
    for (std::size_t i = 0; i < session.size(); ++i) consider(session.component(i).intervalSteps());
  }
  return sent + component.intervalSteps() == next;
}

/// One typed exchange call in the client's order (demlink_c.h, "Exchange orders"):
/// setInputs() stores the call's inputs on the component, readOutputs() copies its latest
/// outputs to the caller.
template <class Read, class Write>
int exchangeStep(Client& c, Component& component, Read&& readOutputs, Write&& setInputs) {
  Session& session = sessionOf(c);
  session.waitCompiled();
  if (!component.exchanged()) {
    throw StateError("component '" + component.name() + "' is not exchanged (communication interval 0)");
  }
  const auto finished = [&] {
    return fail(c, DL_ERR_FINISHED, "the simulation has finished: " + session.finishedInfo().reason());
  };
  if (session.finished()) return finished();
  switch (c.exchange_order) {
    case DL_ORDER_RECEIVE_FIRST:
      if (component.awaitingAnswer() && !session.receive(component)) return finished();
      readOutputs();
      setInputs();
      sendIfDue(session, component);
      return DL_OK;
    case DL_ORDER_SEND_FIRST_SPLIT:
      if (c.split_sent.contains(&component)) {  // the sample's second call
        c.split_sent.erase(&component);
        if (component.awaitingAnswer() && answerEndsThisRound(session, component) && !session.receive(component)) {
          return finished();
        }
      } else {  // the first: an answer that ended since the last sample, then the inputs at t
        if (component.awaitingAnswer() && !session.receive(component)) return finished();
        setInputs();
        if (!sendIfDue(session, component)) {
          session.waitFinished();
          return finished();
        }
        c.split_sent.insert(&component);
      }
      readOutputs();
      return DL_OK;
    default:  // DL_ORDER_SEND_FIRST
      if (component.awaitingAnswer()) {
        throw StateError("component '" + component.name() +
                         "' has an answer in flight (sent in another order); receive it with dl_recv_package");
      }
      requireAloneAtItsStep(session, component);
      setInputs();
      if (!sendIfDue(session, component)) {
        session.waitFinished();
        return finished();
      }
      if (!session.receive(component)) return finished();
      readOutputs();
      return DL_OK;
  }
}

void copyCounts(const v1::CountAndMass* const* values, int n, int* counts, double* masses) {
  if (counts == nullptr || masses == nullptr) throw ArgumentError("counts or masses is NULL");
  for (int i = 0; i < n; ++i) {
    counts[i] = clampCount(values[i]->count());
    masses[i] = values[i]->mass();
  }
}

/// The box of both simulation-box declarations. No end time (NaN or <= 0): the run ends
/// when the tool's clients say Bye.
std::unique_ptr<SimulationBox> simulationBox(const char* name, double timeStep, double endTime, const double* gravity,
                                             const double* boundsLower, const double* boundsUpper) {
  auto box = std::make_unique<SimulationBox>(name != nullptr && name[0] != '\0' ? name : "simulation_box");
  if (given(timeStep)) box->setTimeStep(timeStep);
  if (std::isfinite(endTime) && endTime > 0.0) box->setEndTime(endTime);
  if (gravity != nullptr) box->setInitialGravity(vec(gravity, "gravity"));
  if ((boundsLower == nullptr) != (boundsUpper == nullptr)) {
    throw ArgumentError("boundsLower and boundsUpper must both be given or both be NULL");
  }
  if (boundsLower != nullptr) box->setBounds(vec(boundsLower, "boundsLower"), vec(boundsUpper, "boundsUpper"));
  return box;
}

}  // namespace

void setContactAndIntegrator(v1::SimulationBox& box, long long contactModel, long long integrator,
                             const std::string& where) {
  if (contactModel < 0 || contactModel > 2) {
    throw ArgumentError(where + "contactModel must be 0 (default), 1 (Hertz-Mindlin) or 2 (linear spring-dashpot), got " +
                        std::to_string(contactModel));
  }
  box.set_contact_model(static_cast<v1::SimulationBox::ContactModel>(contactModel));
  if (integrator < 0 || integrator > 2) {
    throw ArgumentError(where + "integrator must be 0 (default), 1 (velocity Verlet) or 2 (explicit Euler), got " +
                        std::to_string(integrator));
  }
  box.set_integrator(static_cast<v1::SimulationBox::Integrator>(integrator));
}

void setSourceSizes(ParticleSource& source, int kind, const std::vector<double>& params) {
  static constexpr std::array<const char*, 5> kNames = {"one radius", "uniform", "linear", "normal", "discrete"};
  static constexpr std::array<std::size_t, 4> kCounts = {1, 2, 4, 4};
  if (kind < 0 || kind > 4) throw ArgumentError("sizeKind must be 0..4 (radius, uniform, linear, normal, discrete)");
  const auto k = static_cast<std::size_t>(kind);
  const bool countOk = k < kCounts.size() ? params.size() == kCounts[k] : !params.empty() && params.size() % 2 == 0;
  if (!countOk) {
    throw ArgumentError(std::string("sizeParams: ") + std::to_string(params.size()) + " values do not fit sizeKind " +
                        std::to_string(kind) + " (" + kNames[k] + ")");
  }
  const auto& p = params;
  switch (kind) {
    case 0: source.setRadius(p[0]); break;
    case 1: source.setRadiusRange(p[0], p[1]); break;
    case 2: source.setLinearSizes(p[0], p[1], p[2], p[3]); break;
    case 3: source.setNormalSizes(p[0], p[1], p[2], p[3]); break;
    default: {
      std::vector<double> radii;
      std::vector<double> weights;
      for (std::size_t i = 0; i + 1 < p.size(); i += 2) {
        radii.push_back(p[i]);
        weights.push_back(p[i + 1]);
      }
      source.setDiscreteSizes(radii, weights);
    }
  }
}

}  // namespace demlink::client::c_abi

using namespace demlink::client;
using namespace demlink::client::c_abi;

extern "C" {

int dl_declare_simulation_box(dl_client* client, const char* name, double interval, double timeStep, double endTime,
                              const double gravity[3], const double boundsLower[3], const double boundsUpper[3],
                              int expectedCount, int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto box = simulationBox(name, timeStep, endTime, gravity, boundsLower, boundsUpper);
    if (expectedCount > 0) box->setExpectedCount(static_cast<std::uint32_t>(expectedCount));
    return declareComponent(c, std::move(box), interval, component);
  });
}

int dl_declare_simulation_box_ex(dl_client* client, const char* name, double interval, double timeStep,
                                 double endTime, const double gravity[3], const double boundsLower[3],
                                 const double boundsUpper[3], int contactModel, int integrator,
                                 double maxImpactVelocity, double restitutionTolerance, double vtkInterval,
                                 int threads, const double frame[12],
                                 int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto box = simulationBox(name, timeStep, endTime, gravity, boundsLower, boundsUpper);
    demlink::v1::SimulationBox& m = box->message();
    setContactAndIntegrator(m, contactModel, integrator, "");
    if (std::isfinite(maxImpactVelocity) && maxImpactVelocity > 0.0) m.set_max_impact_velocity(maxImpactVelocity);
    if (given(restitutionTolerance)) box->setRestitutionTolerance(restitutionTolerance);
    if (given(vtkInterval)) m.mutable_output()->set_vtk_interval(vtkInterval);
    if (threads >= 0) m.set_threads(static_cast<std::uint32_t>(threads));
    if (frame != nullptr) {
      demlink::v1::SimulationBox::Frame& f = *m.mutable_frame();
      *f.mutable_linear_acceleration() = toProto(vec(frame, "frame"));
      *f.mutable_angular_velocity() = toProto(vec(frame + 3, "frame"));
      *f.mutable_angular_acceleration() = toProto(vec(frame + 6, "frame"));
      *f.mutable_origin() = toProto(vec(frame + 9, "frame"));
    }
    return declareComponent(c, std::move(box), interval, component);
  });
}

int dl_simulation_box_set_frame(dl_client* client, int component, const double linearAcceleration[3],
                                const double angularVelocity[3], const double angularAcceleration[3],
                                const double origin[3]) {
  return guarded(client, [&](Client& c) -> int {
    auto& box = typed<SimulationBox>(c, component, "simulation_box");
    box.setFrame(vec(linearAcceleration, "linearAcceleration"), vec(angularVelocity, "angularVelocity"),
                 vec(angularAcceleration, "angularAcceleration"),
                 origin != nullptr ? vec(origin, "origin") : Vec3{});
    return DL_OK;
  });
}

int dl_declare_material(dl_client* client, const char* name, const char* databaseName, double density,
                        double youngsModulus, double poissonRatio, double restitution, double slidingFriction,
                        double rollingFriction, int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto m = std::make_unique<Material>(str(name));
    if (!str(databaseName).empty()) m->setDatabaseName(databaseName);
    if (given(density)) m->setDensity(density);
    if (given(youngsModulus)) m->setYoungsModulus(youngsModulus);
    if (given(poissonRatio)) m->setPoissonRatio(poissonRatio);
    if (given(restitution)) m->setRestitution(restitution);
    if (given(slidingFriction)) m->setSlidingFriction(slidingFriction);
    if (given(rollingFriction)) m->setRollingFriction(rollingFriction);
    return declareComponent(c, std::move(m), 0.0, component);
  });
}

int dl_declare_plane(dl_client* client, const char* name, const double point[3], const double normal[3],
                     const char* material, int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto p = std::make_unique<Plane>(str(name));
    p->setPoint(vec(point, "point")).setNormal(vec(normal, "normal")).setMaterial(str(material));
    return declareComponent(c, std::move(p), 0.0, component);
  });
}

int dl_declare_single_particle(dl_client* client, const char* name, const char* material, const double position[3],
                               const double velocity[3], double diameter, int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto p = std::make_unique<SingleParticle>(str(name));
    p->setMaterial(str(material)).setPosition(vec(position, "position")).setDiameter(diameter);
    if (velocity != nullptr) p->setVelocity(vec(velocity, "velocity"));
    return declareComponent(c, std::move(p), 0.0, component);
  });
}

int dl_declare_rigid_body_stl(dl_client* client, const char* name, double interval, const char* stlFile,
                              const char* material, const double referencePoint[3], const double pose[7], int motion,
                              int* component) {
  return guarded(client, [&](Client& c) -> int {
    if (motion < 0 || motion > 2) throw ArgumentError("motion must be 0, 1 (PREDICTED) or 2 (LAGGED)");
    auto b = std::make_unique<RigidBody>(str(name));
    b->setStlFile(str(stlFile)).setMaterial(str(material)).setMotion(static_cast<demlink::v1::RigidBody::Motion>(motion));
    if (referencePoint != nullptr) b->setReferencePoint(vec(referencePoint, "referencePoint"));
    if (pose != nullptr) b->setInitialPose(vec(pose, "pose"), {pose[3], pose[4], pose[5], pose[6]});
    return declareComponent(c, std::move(b), interval, component);
  });
}

int dl_declare_cad_part(dl_client* client, const char* name, double interval, const char* localStlFile,
                        const char* material, const double referencePoint[3], const double pose[7], int motion,
                        int* component) {
  return guarded(client, [&](Client& c) -> int {
    if (motion < 0 || motion > 2) throw ArgumentError("motion must be 0, 1 (PREDICTED) or 2 (LAGGED)");
    auto b = std::make_unique<RigidBody>(str(name));
    b->setStlData(readStlFile(str(localStlFile))).setMaterial(str(material));
    b->setMotion(static_cast<demlink::v1::RigidBody::Motion>(motion));
    if (referencePoint != nullptr) b->setReferencePoint(vec(referencePoint, "referencePoint"));
    if (pose != nullptr) b->setInitialPose(vec(pose, "pose"), {pose[3], pose[4], pose[5], pose[6]});
    return declareComponent(c, std::move(b), interval, component);
  });
}

int dl_declare_particle_system(dl_client* client, const char* name, const char* file, int checkpoint,
                               int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto p = std::make_unique<ParticleSystem>(str(name));
    if (checkpoint != 0) {
      p->setCheckpointFile(str(file));
    } else {
      p->setCsvFile(str(file));
    }
    return declareComponent(c, std::move(p), 0.0, component);
  });
}

int dl_declare_rigid_body_box(dl_client* client, const char* name, double interval, const double size[3],
                              const char* material, const double pose[7], int motion, int* component) {
  return guarded(client, [&](Client& c) -> int {
    if (motion < 0 || motion > 2) throw ArgumentError("motion must be 0, 1 (PREDICTED) or 2 (LAGGED)");
    auto b = std::make_unique<RigidBody>(str(name));
    b->setBox(vec(size, "size")).setMaterial(str(material)).setMotion(static_cast<demlink::v1::RigidBody::Motion>(motion));
    if (pose != nullptr) b->setInitialPose(vec(pose, "pose"), {pose[3], pose[4], pose[5], pose[6]});
    return declareComponent(c, std::move(b), interval, component);
  });
}

int dl_declare_region_sensor_box(dl_client* client, const char* name, double interval, const double centre[3],
                                 const double size[3], const char* attachedTo, int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto s = std::make_unique<RegionSensor>(str(name));
    s->setBox(vec(centre, "centre"), vec(size, "size"));
    if (!str(attachedTo).empty()) s->attachTo(attachedTo);
    return declareComponent(c, std::move(s), interval, component);
  });
}

int dl_declare_region_sensor_box_oriented(dl_client* client, const char* name, double interval,
                                          const double centre[3], const double size[3], const double orientation[4],
                                          const char* attachedTo, int* component) {
  return declareOrientedBox<RegionSensor>(client, name, interval, centre, size, orientation, attachedTo, component);
}

int dl_declare_region_sensor_sphere(dl_client* client, const char* name, double interval, const double centre[3],
                                    double radius, const char* attachedTo, int* component) {
  return declareSphere<RegionSensor>(client, name, interval, centre, radius, attachedTo, component);
}

int dl_declare_flow_sensor_disc(dl_client* client, const char* name, double interval, const double centre[3],
                                const double normal[3], double radius, const char* attachedTo, int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto s = std::make_unique<FlowSensor>(str(name));
    s->setDisc(vec(centre, "centre"), vec(normal, "normal"), radius);
    if (!str(attachedTo).empty()) s->attachTo(attachedTo);
    return declareComponent(c, std::move(s), interval, component);
  });
}

int dl_declare_flow_sensor_rectangle(dl_client* client, const char* name, double interval, const double centre[3],
                                     const double normal[3], double length, double width, const double lengthAxis[3],
                                     const char* attachedTo, int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto s = std::make_unique<FlowSensor>(str(name));
    s->setRectangle(vec(centre, "centre"), vec(normal, "normal"), length, width,
                    lengthAxis != nullptr ? vec(lengthAxis, "lengthAxis") : Vec3{});
    if (!str(attachedTo).empty()) s->attachTo(attachedTo);
    return declareComponent(c, std::move(s), interval, component);
  });
}

int dl_declare_particle_source_box(dl_client* client, const char* name, double interval, const char* material,
                                   const double centre[3], const double halfExtents[3], double rMin, double rMax,
                                   double ratePerSecond, double rateKgPerSecond, const double velocity[3], uint64_t seed,
                                   int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto s = std::make_unique<ParticleSource>(str(name));
    s->setMaterial(str(material)).setBox(vec(centre, "centre"), vec(halfExtents, "halfExtents"));
    s->setRadiusRange(rMin, rMax).setSeed(seed);
    if (given(ratePerSecond)) s->setRateParticles(ratePerSecond);
    if (given(rateKgPerSecond)) s->setRateMass(rateKgPerSecond);
    if (velocity != nullptr) s->setVelocity(vec(velocity, "velocity"));
    return declareComponent(c, std::move(s), interval, component);
  });
}

int dl_declare_particle_source(dl_client* client, const char* name, double interval, const char* material, int region,
                               const double* regionParams, int sizeKind, const double* sizeParams, int nSizeParams,
                               double ratePerSecond, double rateKgPerSecond, const double velocity[3], uint64_t seed,
                               int* component) {
  return guarded(client, [&](Client& c) -> int {
    if (regionParams == nullptr) throw ArgumentError("regionParams is NULL");
    if (nSizeParams < 0 || (nSizeParams > 0 && sizeParams == nullptr)) {
      throw ArgumentError("sizeParams: " + std::to_string(nSizeParams) + " values requested from a NULL array");
    }
    auto s = std::make_unique<ParticleSource>(str(name));
    s->setMaterial(str(material)).setSeed(seed);
    if (region == 0) {
      s->setBox(vec(regionParams, "centre"), vec(regionParams + 3, "halfExtents"));
    } else if (region == 1) {
      s->setDisc(vec(regionParams, "centre"), vec(regionParams + 3, "normal"), regionParams[6], regionParams[7]);
    } else {
      throw ArgumentError("region must be 0 (box) or 1 (disc), not " + std::to_string(region));
    }
    setSourceSizes(*s, sizeKind, std::vector<double>(sizeParams, sizeParams + nSizeParams));
    if (given(ratePerSecond)) s->setRateParticles(ratePerSecond);
    if (given(rateKgPerSecond)) s->setRateMass(rateKgPerSecond);
    if (velocity != nullptr) s->setVelocity(vec(velocity, "velocity"));
    return declareComponent(c, std::move(s), interval, component);
  });
}

int dl_declare_particle_sink_box(dl_client* client, const char* name, double interval, const double centre[3],
                                 const double size[3], int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto s = std::make_unique<ParticleSink>(str(name));
    s->setBox(vec(centre, "centre"), vec(size, "size"));
    return declareComponent(c, std::move(s), interval, component);
  });
}

int dl_declare_particle_sink_box_oriented(dl_client* client, const char* name, double interval,
                                          const double centre[3], const double size[3], const double orientation[4],
                                          const char* attachedTo, int* component) {
  return declareOrientedBox<ParticleSink>(client, name, interval, centre, size, orientation, attachedTo, component);
}

int dl_declare_particle_sink_sphere(dl_client* client, const char* name, double interval, const double centre[3],
                                    double radius, const char* attachedTo, int* component) {
  return declareSphere<ParticleSink>(client, name, interval, centre, radius, attachedTo, component);
}

int dl_declare_pit_generator(dl_client* client, const char* name, const char* material, const double lower[3],
                             const double upper[3], double rMin, double rMax, double targetHeight, uint64_t seed,
                             int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto p = std::make_unique<PitGenerator>(str(name));
    p->setMaterial(str(material)).setBox(vec(lower, "lower"), vec(upper, "upper")).setRadiusRange(rMin, rMax);
    p->setTargetHeight(targetHeight).setSeed(seed);
    return declareComponent(c, std::move(p), 0.0, component);
  });
}

/// The rule's law, fraction and materials from dl_declare_parallel_bonds' arguments.
std::unique_ptr<ParallelBonds> parallelBonds(const char* name, const double* properties, const char* materials,
                                             uint64_t seed) {
  if (properties == nullptr) throw ArgumentError("properties is NULL (8 values expected)");
  auto b = std::make_unique<ParallelBonds>(str(name));
  b->setStiffnessPerArea(properties[0], properties[1]).setStrength(properties[2], properties[3]);
  b->setGapTolerance(properties[4]).setCreateTime(properties[6]);
  if (!std::isnan(properties[5])) b->setRadiusMultiplier(properties[5]);
  b->setFraction(std::isnan(properties[7]) ? 1.0 : properties[7], seed);
  std::istringstream names(str(materials));
  for (std::string material; names >> material;) b->addMaterial(material);
  return b;
}

int dl_declare_parallel_bonds(dl_client* client, const char* name, const double properties[8], const double box[6],
                              const char* materials, uint64_t seed, int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto b = parallelBonds(name, properties, materials, seed);
    if (box != nullptr) b->setBox(vec(box, "box"), vec(box + 3, "box size"));
    return declareComponent(c, std::move(b), 0.0, component);
  });
}

int dl_declare_parallel_bonds_region(dl_client* client, const char* name, const double properties[8], int regionKind,
                                     const double centre[3], const double size[3], const double orientation[4],
                                     double radius, const char* attachedTo, const char* materials, uint64_t seed,
                                     int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto b = parallelBonds(name, properties, materials, seed);
    if (regionKind == DL_REGION_BOX) {
      b->setBox(vec(centre, "centre"), vec(size, "size"), quat(orientation));
    } else if (regionKind == DL_REGION_SPHERE) {
      b->setSphere(vec(centre, "centre"), radius);
    } else if (regionKind != DL_REGION_EVERYWHERE) {
      throw ArgumentError("regionKind = " + std::to_string(regionKind) +
                          ": must be DL_REGION_EVERYWHERE (0), DL_REGION_BOX (1) or DL_REGION_SPHERE (2)");
    }
    if (!str(attachedTo).empty()) {
      if (regionKind == DL_REGION_EVERYWHERE) {
        throw ArgumentError("attachedTo = \"" + str(attachedTo) + "\": a rule without a region has nothing to attach");
      }
      b->attachTo(attachedTo);
    }
    return declareComponent(c, std::move(b), 0.0, component);
  });
}

int dl_declare_pit_generator_clods(dl_client* client, const char* name, const char* material, const double lower[3],
                                   const double upper[3], double rMin, double rMax, double targetHeight, uint64_t seed,
                                   const double clods[2], const char* bondsName, int* component) {
  return guarded(client, [&](Client& c) -> int {
    if (clods == nullptr) throw ArgumentError("clods is NULL (fraction, radius expected)");
    auto p = std::make_unique<PitGenerator>(str(name));
    p->setMaterial(str(material)).setBox(vec(lower, "lower"), vec(upper, "upper")).setRadiusRange(rMin, rMax);
    p->setTargetHeight(targetHeight).setSeed(seed).setClods(clods[0], clods[1], str(bondsName));
    return declareComponent(c, std::move(p), 0.0, component);
  });
}

int dl_declare_particle_view(dl_client* client, const char* name, double interval, int maxCount, int* component) {
  return guarded(client, [&](Client& c) -> int {
    auto v = std::make_unique<ParticleView>(str(name));
    v->setMaxCount(static_cast<std::uint32_t>(std::max(maxCount, 0)));
    return declareComponent(c, std::move(v), interval, component);
  });
}

int dl_declare_mass_spring_box(dl_client* client, const char* name, double interval, const char* material,
                               const double lo[3], const double hi[3], double nodeSpacing, const double springs[3],
                               const double breakLimits[2], int fixedCount, const double* fixedRegions,
                               int drivenCount, const double* drivenRegions, const double drivenReference[3],
                               const char* attachedTo, int* component) {
  return guarded(client, [&](Client& c) -> int {
    if (springs == nullptr) throw ArgumentError("springs is NULL");
    auto b = std::make_unique<MassSpringBody>(str(name));
    b->setBox(vec(lo, "lo"), vec(hi, "hi"), nodeSpacing).setMaterial(str(material));
    b->setSprings(springs[0], springs[1], springs[2]);
    if (breakLimits != nullptr && given(breakLimits[0])) b->message().set_break_force(breakLimits[0]);
    if (breakLimits != nullptr && given(breakLimits[1])) b->message().set_break_strain(breakLimits[1]);
    constrain(b->message(), fixedCount, fixedRegions, drivenCount, drivenRegions, drivenReference, attachedTo);
    return declareComponent(c, std::move(b), interval, component);
  });
}

int dl_declare_fem_mesh(dl_client* client, const char* name, double interval, const char* material,
                        const char* mshFile, const double elastic[3], const double rayleigh[2], int fixedCount,
                        const double* fixedRegions, int drivenCount, const double* drivenRegions,
                        const double drivenReference[3], const char* attachedTo, int* component) {
  return guarded(client, [&](Client& c) -> int {
    if (elastic == nullptr) throw ArgumentError("elastic is NULL");
    auto b = std::make_unique<FemBody>(str(name));
    b->setMesh(str(mshFile), elastic[0], elastic[1], elastic[2]).setMaterial(str(material));
    if (rayleigh != nullptr) b->setRayleigh(rayleigh[0], rayleigh[1]);
    constrain(b->message(), fixedCount, fixedRegions, drivenCount, drivenRegions, drivenReference, attachedTo);
    return declareComponent(c, std::move(b), interval, component);
  });
}

int dl_simulation_box_exchange(dl_client* client, int component, const double gravity[3], double out[4],
                               int* particleCount) {
  return guarded(client, [&](Client& c) -> int {
    if (out == nullptr || particleCount == nullptr) throw ArgumentError("out or particleCount is NULL");
    auto& box = typed<SimulationBox>(c, component, "simulation_box");
    return exchangeStep(
        c, box,
        [&] {
          out[0] = box.time();
          out[1] = box.totalMass();
          out[2] = box.kineticEnergy();
          out[3] = box.stepRate();
          *particleCount = clampCount(box.particleCount());
        },
        [&] {
          if (gravity != nullptr) box.setGravity(vec(gravity, "gravity"));
        });
  });
}

int dl_rigid_body_exchange(dl_client* client, int component, const double pose[7], const double twist[6],
                           double wrenchOut[12]) {
  return guarded(client, [&](Client& c) -> int {
    if (pose == nullptr || twist == nullptr || wrenchOut == nullptr) throw ArgumentError("pose, twist or wrenchOut is NULL");
    auto& body = typed<RigidBody>(c, component, "rigid_body");
    return exchangeStep(
        c, body,
        [&] {
          flatten({body.meanForce(), body.meanTorque(), body.force(), body.torque()}, wrenchOut);
        },
        [&] {
          body.setPose({pose[0], pose[1], pose[2]}, {pose[3], pose[4], pose[5], pose[6]});
          body.setVelocity({twist[0], twist[1], twist[2]}, {twist[3], twist[4], twist[5]});
        });
  });
}

int dl_deformable_body_exchange(dl_client* client, int component, const double pose[7], const double twist[6],
                                double reactionsOut[12], int capacity, double* displacements, int* count,
                                int* broken) {
  return guarded(client, [&](Client& c) -> int {
    if (reactionsOut == nullptr || count == nullptr || broken == nullptr) {
      throw ArgumentError("reactionsOut, count or broken is NULL");
    }
    if (capacity < 0 || (capacity > 0 && displacements == nullptr)) {
      throw ArgumentError("deformable body: bad capacity or NULL displacements");
    }
    auto& body = typed<DeformableBody>(c, component, "mass_spring_body or fem_body");
    return exchangeStep(
        c, body,
        [&] {
          flatten({body.drivenForce(), body.drivenTorque(), body.fixedForce(), body.fixedTorque()}, reactionsOut);
          const std::vector<Vec3> u = body.displacements();
          *count = clampCount(u.size());
          for (std::size_t i = 0; i < u.size() && i < static_cast<std::size_t>(capacity); ++i) {
            displacements[3 * i] = u[i].x;
            displacements[3 * i + 1] = u[i].y;
            displacements[3 * i + 2] = u[i].z;
          }
          *broken = clampCount(body.brokenSprings());
        },
        [&] {
          if (pose == nullptr) return;
          body.setDrivenPose({pose[0], pose[1], pose[2]}, {pose[3], pose[4], pose[5], pose[6]});
          if (twist != nullptr) body.setDrivenVelocity({twist[0], twist[1], twist[2]}, {twist[3], twist[4], twist[5]});
        });
  });
}

int dl_region_sensor_read(dl_client* client, int component, int* count, double out[7]) {
  return dl_region_sensor_read_bonds(client, component, count, out, nullptr);
}

int dl_region_sensor_read_bonds(dl_client* client, int component, int* count, double out[7], int bonds[2]) {
  return guarded(client, [&](Client& c) -> int {
    if (count == nullptr || out == nullptr) throw ArgumentError("count or out is NULL");
    auto& sensor = typed<RegionSensor>(c, component, "region_sensor");
    return exchangeStep(
        c, sensor,
        [&] {
          *count = clampCount(sensor.count());
          const Vec3 com = sensor.centreOfMass();
          const Vec3 v = sensor.meanVelocity();
          const double values[7] = {sensor.mass(), com.x, com.y, com.z, v.x, v.y, v.z};
          std::copy(values, values + 7, out);
          if (bonds != nullptr) {
            bonds[0] = clampCount(sensor.bondsIntact());
            bonds[1] = clampCount(sensor.bondsBroken());
          }
        },
        [] {});
  });
}

int dl_flow_sensor_read(dl_client* client, int component, int counts[4], double masses[4]) {
  return guarded(client, [&](Client& c) -> int {
    auto& sensor = typed<FlowSensor>(c, component, "flow_sensor");
    return exchangeStep(
        c, sensor,
        [&] {
          const auto& o = sensor.outputs().flow_sensor();
          const demlink::v1::CountAndMass* values[4] = {&o.positive_interval(), &o.negative_interval(), &o.positive_total(),
                                               &o.negative_total()};
          copyCounts(values, 4, counts, masses);
        },
        [] {});
  });
}

int dl_particle_source_read(dl_client* client, int component, int counts[3], double masses[3]) {
  return guarded(client, [&](Client& c) -> int {
    auto& source = typed<ParticleSource>(c, component, "particle_source");
    return exchangeStep(
        c, source,
        [&] {
          const auto& o = source.outputs().particle_source();
          const demlink::v1::CountAndMass* values[3] = {&o.interval(), &o.total(), &o.shortfall_total()};
          copyCounts(values, 3, counts, masses);
        },
        [] {});
  });
}

int dl_particle_sink_read(dl_client* client, int component, int counts[2], double masses[2]) {
  return guarded(client, [&](Client& c) -> int {
    auto& sink = typed<ParticleSink>(c, component, "particle_sink");
    return exchangeStep(
        c, sink,
        [&] {
          const auto& o = sink.outputs().particle_sink();
          const demlink::v1::CountAndMass* values[2] = {&o.interval(), &o.total()};
          copyCounts(values, 2, counts, masses);
        },
        [] {});
  });
}

int dl_region_sensor_set_region(dl_client* client, int component, const double centre[3],
                                const double orientation[4], const double size[3], double radius) {
  return guarded(client, [&](Client& c) -> int {
    auto& sensor = typed<RegionSensor>(c, component, "region_sensor");
    if (centre != nullptr) sensor.moveTo(vec(centre, "centre"));
    if (orientation != nullptr) sensor.turnTo({orientation[0], orientation[1], orientation[2], orientation[3]});
    if (size != nullptr) sensor.resizeBox(vec(size, "size"));
    if (!std::isnan(radius)) sensor.resizeSphere(radius);
    return DL_OK;
  });
}

int dl_particle_source_set_enabled(dl_client* client, int component, int on) {
  return guarded(client, [&](Client& c) -> int {
    typed<ParticleSource>(c, component, "particle_source").setEnabled(on != 0);
    return DL_OK;
  });
}

int dl_particle_source_set_rate(dl_client* client, int component, double rate) {
  return guarded(client, [&](Client& c) -> int {
    if (!std::isfinite(rate) || rate < 0.0) throw ArgumentError("rate must be finite and >= 0, got " + std::to_string(rate));
    typed<ParticleSource>(c, component, "particle_source").changeRate(rate);
    return DL_OK;
  });
}

int dl_particle_sink_set_enabled(dl_client* client, int component, int on) {
  return guarded(client, [&](Client& c) -> int {
    typed<ParticleSink>(c, component, "particle_sink").setEnabled(on != 0);
    return DL_OK;
  });
}

int dl_particle_sink_move(dl_client* client, int component, const double centre[3]) {
  return guarded(client, [&](Client& c) -> int {
    typed<ParticleSink>(c, component, "particle_sink").moveTo(vec(centre, "centre"));
    return DL_OK;
  });
}

int dl_particle_view_read_ex(dl_client* client, int component, int capacity, double* positions,
                             double* velocities, double* radii, uint64_t* ids, int* count) {
  return guarded(client, [&](Client& c) -> int {
    if (capacity < 0 || count == nullptr || (capacity > 0 && (positions == nullptr || radii == nullptr))) {
      throw ArgumentError("particle view: bad capacity or NULL output arrays");
    }
    auto& view = typed<ParticleView>(c, component, "particle_view");
    return exchangeStep(
        c, view,
        [&] {
          const auto& o = view.view();
          const int listed = o.radii_size();
          *count = listed;
          const int n = std::min(listed, capacity);
          const auto triple = [](const google::protobuf::RepeatedField<float>& from, int j) {
            return j < from.size() ? static_cast<double>(from.Get(j)) : 0.0;
          };
          for (int i = 0; i < n; ++i) {
            for (int k = 0; k < 3; ++k) {
              positions[3 * i + k] = triple(o.positions(), 3 * i + k);
              if (velocities != nullptr) velocities[3 * i + k] = triple(o.velocities(), 3 * i + k);
            }
            radii[i] = o.radii(i);
            if (ids != nullptr) ids[i] = i < o.ids_size() ? o.ids(i) : 0;
          }
        },
        [] {});
  });
}

int dl_particle_view_read(dl_client* client, int component, int capacity, double* positions, double* radii,
                          int* count) {
  return dl_particle_view_read_ex(client, component, capacity, positions, nullptr, radii, nullptr, count);
}

}  // extern "C"
