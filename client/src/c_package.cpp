/// Generic packages of the C ABI: the dl_package functions and the conversions between
/// the documented array layout (demlink_c.h, docs/c_abi.md) and the typed components.
/// Layout mistakes (too few values, unknown kind) are reported by name and index, because
/// a Modelica user sees nothing but this message.
#include <climits>
#include <cmath>
#include <cstdio>
#include <limits>
#include <new>

#include "c_internal.hpp"

namespace demlink::client::c_abi {
namespace {

/// Reads the layout with bounds checks that name the kind and index.
class Reader {
 public:
  Reader(const Package& package, std::string kind) : p_(package), kind_(std::move(kind)) {}
  [[nodiscard]] bool hasReal(std::size_t i) const { return i < p_.reals.size() && !std::isnan(p_.reals[i]); }
  [[nodiscard]] double real(std::size_t i) const {
    if (i >= p_.reals.size()) {
      throw ArgumentError(kind_ + ": reals[" + std::to_string(i) + "] is required (the package has " +
                          std::to_string(p_.reals.size()) + ")");
    }
    return p_.reals[i];
  }
  [[nodiscard]] Vec3 vec(std::size_t i) const { return {real(i), real(i + 1), real(i + 2)}; }
  [[nodiscard]] Quat quat(std::size_t i) const { return {real(i), real(i + 1), real(i + 2), real(i + 3)}; }
  [[nodiscard]] long long integer(std::size_t i, long long fallback) const {
    return i < p_.ints.size() ? p_.ints[i] : fallback;
  }
  [[nodiscard]] std::string text(std::size_t i) const { return i < p_.strings.size() ? p_.strings[i] : std::string(); }

 private:
  const Package& p_;
  std::string kind_;
};

void pushCount(Package& p, const v1::CountAndMass& value) {
  p.ints.push_back(static_cast<long long>(std::min<std::uint64_t>(value.count(), LLONG_MAX)));
  p.reals.push_back(value.mass());
}

void pushVec(Package& p, const v1::Vector3& v) {
  p.reals.insert(p.reals.end(), {v.x(), v.y(), v.z()});
}

template <class T>
int copyOut(const std::vector<T>& values, T* out, int capacity, int* count) {
  if (count != nullptr) *count = static_cast<int>(std::min<std::size_t>(values.size(), INT_MAX));
  if (out == nullptr) return capacity == 0 ? DL_OK : DL_ERR_ARGUMENT;
  if (capacity < 0) return DL_ERR_ARGUMENT;
  const std::size_t n = std::min(values.size(), static_cast<std::size_t>(capacity));
  std::copy(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(n), out);
  return n < values.size() ? DL_ERR_CAPACITY : DL_OK;
}

}  // namespace

std::string readStlFile(const std::string& path) {
  // stdio instead of ifstream: GCC 12's -Wnull-dereference misfires inside <streambuf>.
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) throw ArgumentError("rigid_body: cannot read STL file '" + path + "'");
  std::string bytes;
  char chunk[65536];
  std::size_t n = 0;
  while ((n = std::fread(chunk, 1, sizeof chunk, file)) > 0) bytes.append(chunk, n);
  std::fclose(file);
  return bytes;
}

Package* asPackage(dl_package* handle) {
  auto* p = static_cast<Package*>(handle);
  return p != nullptr && p->tag == kPackageTag ? p : nullptr;
}
const Package* asPackage(const dl_package* handle) {
  const auto* p = static_cast<const Package*>(handle);
  return p != nullptr && p->tag == kPackageTag ? p : nullptr;
}

std::unique_ptr<Component> componentFromPackage(const Package& p) {
  if (p.strings.size() < 2 || p.strings[1].empty()) {
    throw ArgumentError("declare package: strings[0] = kind and strings[1] = name are required");
  }
  const std::string& kind = p.strings[0];
  const std::string& name = p.strings[1];
  const Reader r(p, kind);
  const double interval = r.hasReal(0) ? r.real(0) : 0.0;
  std::unique_ptr<Component> out;
  if (kind == "simulation_box") {
    auto c = std::make_unique<SimulationBox>(name);
    if (r.hasReal(1)) c->setTimeStep(r.real(1));
    c->setEndTime(r.real(2));
    if (r.hasReal(3)) c->setInitialGravity(r.vec(3));
    if (p.reals.size() >= 12) c->setBounds(r.vec(6), r.vec(9));
    if (r.integer(0, 0) > 0) c->setExpectedCount(static_cast<std::uint32_t>(r.integer(0, 0)));
    for (std::size_t i = 2; i < p.strings.size(); ++i) c->addExpectedName(p.strings[i]);
    if (r.hasReal(12)) {
      if (!(r.real(12) >= 0.0)) throw ArgumentError("simulation_box: reals[12] (VTK interval) must be >= 0 s");
      c->message().mutable_output()->set_vtk_interval(r.real(12));
    }
    if (r.hasReal(13)) c->setRestitutionTolerance(r.real(13));
    const long long threads = r.integer(1, -1);
    if (threads > static_cast<long long>(UINT32_MAX)) throw ArgumentError("simulation_box: ints[1] (threads) is too large");
    if (threads >= 0) c->message().set_threads(static_cast<std::uint32_t>(threads));
    // The speed/accuracy settings (docs/physics.md, docs/accuracy.md): contact law,
    // integrator, fidelity preset, largest impact speed, coarse graining, softening.
    setContactAndIntegrator(c->message(), r.integer(2, 0), r.integer(3, 0), "simulation_box: ints[2..3]: ");
    const long long fidelity = r.integer(4, 0);
    if (fidelity < 0 || fidelity > 3) {
      throw ArgumentError("simulation_box: ints[4] (fidelity) must be 0 (none), 1 (draft), 2 (engineering) or "
                          "3 (validation), got " + std::to_string(fidelity));
    }
    c->message().set_fidelity(static_cast<v1::SimulationBox::Fidelity>(fidelity));
    if (r.hasReal(14)) c->message().set_max_impact_velocity(r.real(14));
    if (r.hasReal(15)) c->message().set_coarse_graining(r.real(15));
    if (r.hasReal(16)) c->message().mutable_watchdog()->set_max_overlap_fraction(r.real(16));
    if (r.hasReal(17)) c->message().set_modulus_scale(r.real(17));
    out = std::move(c);
  } else if (kind == "material") {
    auto c = std::make_unique<Material>(name);
    if (!r.text(2).empty()) c->setDatabaseName(r.text(2));
    if (r.hasReal(1)) c->setDensity(r.real(1));
    if (r.hasReal(2)) c->setYoungsModulus(r.real(2));
    if (r.hasReal(3)) c->setPoissonRatio(r.real(3));
    if (r.hasReal(4)) c->setRestitution(r.real(4));
    if (r.hasReal(5)) c->setSlidingFriction(r.real(5));
    if (r.hasReal(6)) c->setRollingFriction(r.real(6));
    out = std::move(c);
  } else if (kind == "plane") {
    auto c = std::make_unique<Plane>(name);
    c->setMaterial(r.text(2)).setPoint(r.vec(1)).setNormal(r.vec(4));
    out = std::move(c);
  } else if (kind == "single_particle") {
    auto c = std::make_unique<SingleParticle>(name);
    c->setMaterial(r.text(2)).setPosition(r.vec(1)).setVelocity(r.vec(4)).setDiameter(r.real(7));
    out = std::move(c);
  } else if (kind == "particle_system") {
    auto c = std::make_unique<ParticleSystem>(name);
    if (r.integer(0, 0) == 1) {
      c->setCheckpointFile(r.text(2));
    } else {
      c->setCsvFile(r.text(2));
    }
    out = std::move(c);
  } else if (kind == "particle_source") {
    auto c = std::make_unique<ParticleSource>(name);
    c->setMaterial(r.text(2));
    const long long region = r.integer(1, 0);
    if (region == 0) c->setBox(r.vec(1), r.vec(4));
    else if (region == 1) c->setDisc(r.vec(1), r.vec(4), r.real(16), r.hasReal(17) ? r.real(17) : 0.0);
    else throw ArgumentError("particle_source: ints[1] (region) must be 0 (box) or 1 (disc)");
    // ints[2] size kind as in dl_declare_particle_source: r_min, r_max at [7], [8], the linear
    // weights or the normal's mean and std at [18], [19], discrete (radius, weight) pairs from [20].
    const long long sizeKind = r.integer(2, 1);
    if (sizeKind < 0 || sizeKind > 4) throw ArgumentError("particle_source: ints[2] (size kind) must be 0..4");
    std::vector<double> sizes;
    if (sizeKind == 0) sizes = {r.real(7)};
    else if (sizeKind == 1) sizes = {r.real(7), r.real(8)};
    else if (sizeKind == 2) sizes = {r.real(7), r.real(8), r.real(18), r.real(19)};
    else if (sizeKind == 3) sizes = {r.real(18), r.real(19), r.real(7), r.real(8)};
    else if (p.reals.size() > 20) sizes.assign(p.reals.begin() + 20, p.reals.end());
    setSourceSizes(*c, static_cast<int>(sizeKind), sizes);
    if (r.hasReal(9)) c->setRateParticles(r.real(9));
    if (r.hasReal(10)) c->setRateMass(r.real(10));
    if (r.hasReal(11)) c->setVelocity(r.vec(11));
    if (r.hasReal(14)) c->setStartTime(r.real(14));
    if (r.hasReal(15)) c->setStopTime(r.real(15));
    c->setSeed(static_cast<std::uint64_t>(r.integer(0, 0)));
    if (!r.text(3).empty()) c->attachTo(r.text(3));
    if (!r.text(4).empty()) c->setClumpTemplate(r.text(4));
    out = std::move(c);
  } else if (kind == "clump_template") {
    // reals[1..]: (x, y, z, radius) per sphere.
    if (p.reals.size() < 5 || (p.reals.size() - 1) % 4 != 0) {
      throw ArgumentError("clump_template: reals[1..] must be (x, y, z, radius) per sphere, at least one sphere; got " +
                          std::to_string(p.reals.empty() ? 0 : p.reals.size() - 1) + " numbers");
    }
    auto c = std::make_unique<ClumpTemplate>(name);
    for (std::size_t k = 1; k + 3 < p.reals.size(); k += 4) {
      c->addSphere(Vec3{p.reals[k], p.reals[k + 1], p.reals[k + 2]}, p.reals[k + 3]);
    }
    out = std::move(c);
  } else if (kind == "particle_sink" || kind == "region_sensor") {
    const long long shape = r.integer(0, 0);
    if (shape != 0 && shape != 1) throw ArgumentError(kind + ": ints[0] (shape) must be 0 (box) or 1 (sphere)");
    const Quat q = r.hasReal(7) ? r.quat(7) : Quat{};
    auto place = [&](auto& c) {
      if (shape == 0) c.setBox(r.vec(1), r.vec(4), q);
      else c.setSphere(r.vec(1), r.real(4));
      if (!r.text(2).empty()) c.attachTo(r.text(2));
      if (r.hasReal(11)) c.setVelocity(r.vec(11));
    };
    if (kind == "particle_sink") {
      auto c = std::make_unique<ParticleSink>(name);
      place(*c);
      out = std::move(c);
    } else {
      auto c = std::make_unique<RegionSensor>(name);
      place(*c);
      out = std::move(c);
    }
  } else if (kind == "flow_sensor") {
    auto c = std::make_unique<FlowSensor>(name);
    const long long shape = r.integer(0, 0);
    if (shape == 0) {
      c->setRectangle(r.vec(1), r.vec(4), r.real(7), r.real(8), r.hasReal(9) ? r.vec(9) : Vec3{});
    } else if (shape == 1) {
      c->setDisc(r.vec(1), r.vec(4), r.real(7));
    } else {
      throw ArgumentError("flow_sensor: ints[0] (shape) must be 0 (rectangle) or 1 (disc)");
    }
    if (!r.text(2).empty()) c->attachTo(r.text(2));
    if (r.hasReal(12)) c->setVelocity(r.vec(12));
    out = std::move(c);
  } else if (kind == "pit_generator") {
    auto c = std::make_unique<PitGenerator>(name);
    c->setMaterial(r.text(2)).setBox(r.vec(1), r.vec(4)).setRadiusRange(r.real(7), r.real(8));
    c->setTargetHeight(r.real(9)).setSeed(static_cast<std::uint64_t>(r.integer(0, 0)));
    if (r.hasReal(10)) c->setClods(r.real(10), r.hasReal(11) ? r.real(11) : 0.0, r.text(3));
    if (!r.text(4).empty()) c->setClumpTemplate(r.text(4));
    out = std::move(c);
  } else if (kind == "parallel_bonds") {
    auto c = std::make_unique<ParallelBonds>(name);
    c->setStiffnessPerArea(r.real(1), r.real(2)).setStrength(r.real(3), r.real(4)).setGapTolerance(r.real(5));
    if (r.hasReal(6)) c->setRadiusMultiplier(r.real(6));
    if (r.hasReal(7)) c->setCreateTime(r.real(7));
    c->setFraction(r.hasReal(8) ? r.real(8) : 1.0, static_cast<std::uint64_t>(r.integer(0, 0)));
    // ints[1] (the region kind) selects the layout with any region; without it reals[9..14]
    // are a box and every string from strings[2] a material (demlink_c.h).
    std::size_t firstMaterial = 2;
    if (p.ints.size() >= 2) {
      const long long region = r.integer(1, DL_REGION_EVERYWHERE);
      if (region == DL_REGION_BOX) {
        c->setBox(r.vec(9), r.vec(12), r.hasReal(15) ? r.quat(15) : Quat{});
      } else if (region == DL_REGION_SPHERE) {
        c->setSphere(r.vec(9), r.real(12));
      } else if (region != DL_REGION_EVERYWHERE) {
        throw ArgumentError("parallel_bonds: ints[1] (region) = " + std::to_string(region) +
                            ": must be 0 (everywhere), 1 (box) or 2 (sphere)");
      }
      if (!r.text(2).empty()) {
        if (region == DL_REGION_EVERYWHERE) {
          throw ArgumentError("parallel_bonds: strings[2] (attached body) = \"" + r.text(2) +
                              "\": a rule without a region (ints[1] = 0) has nothing to attach");
        }
        c->attachTo(r.text(2));
      }
      firstMaterial = 3;
    } else if (r.hasReal(9)) {
      c->setBox(r.vec(9), r.vec(12));
    }
    for (std::size_t k = firstMaterial; k < p.strings.size(); ++k) {
      if (!p.strings[k].empty()) c->addMaterial(p.strings[k]);
    }
    out = std::move(c);
  } else if (kind == "rigid_body") {
    auto c = std::make_unique<RigidBody>(name);
    const long long geometry = r.integer(0, 0);
    if (geometry == 0) c->setStlFile(r.text(3));
    else if (geometry == 1) c->setBox(r.vec(11));
    else if (geometry == 2) c->setStlData(readStlFile(r.text(3)));
    else throw ArgumentError("rigid_body: ints[0] (geometry) must be 0 (STL on the server), 1 (box) or 2 (STL on the client)");
    const long long motion = r.integer(1, 0);
    if (motion < 0 || motion > 2) throw ArgumentError("rigid_body: ints[1] (motion) must be 0, 1 or 2");
    c->setMaterial(r.text(2)).setMotion(static_cast<v1::RigidBody::Motion>(motion));
    if (r.hasReal(1)) c->setReferencePoint(r.vec(1));
    if (r.hasReal(4)) c->setInitialPose(r.vec(4), p.reals.size() >= 11 ? r.quat(7) : Quat{});
    out = std::move(c);
  } else if (kind == "particle_view") {
    auto c = std::make_unique<ParticleView>(name);
    c->setMaxCount(static_cast<std::uint32_t>(std::max(0LL, r.integer(0, 0))));
    out = std::move(c);
  } else {
    throw ArgumentError("declare package: kind '" + kind +
                        "' has no generic layout (simulation_box, material, plane, single_particle, "
                        "particle_system, particle_source, particle_sink, pit_generator, parallel_bonds, rigid_body, "
                        "region_sensor, flow_sensor, particle_view)");
  }
  out->setCommunicationInterval(interval);
  return out;
}

void applyInputs(Component& component, const Package& p) {
  const std::string kind = component.kind();
  const Reader r(p, kind);
  if (auto* body = dynamic_cast<RigidBody*>(&component)) {
    if (p.reals.size() != 13) {
      throw ArgumentError("rigid_body input: 13 reals expected (x y z qw qx qy qz vx vy vz wx wy wz), got " +
                          std::to_string(p.reals.size()));
    }
    body->setPose(r.vec(0), r.quat(3));
    body->setVelocity(r.vec(7), r.vec(10));
  } else if (auto* deformable = dynamic_cast<DeformableBody*>(&component)) {
    if (p.reals.empty()) return;  // no pose: the driven nodes keep their last one
    if (p.reals.size() != 7 && p.reals.size() != 13) {
      throw ArgumentError(kind + " input: 7 reals (x y z qw qx qy qz) or 13 (with vx vy vz wx wy wz) expected, got " +
                          std::to_string(p.reals.size()));
    }
    deformable->setDrivenPose(r.vec(0), r.quat(3));
    if (p.reals.size() == 13) deformable->setDrivenVelocity(r.vec(7), r.vec(10));
  } else if (auto* box = dynamic_cast<SimulationBox*>(&component)) {
    if (r.hasReal(0)) box->setGravity(r.vec(0));
    if (p.reals.size() >= 15) box->setFrame(r.vec(3), r.vec(6), r.vec(9), r.vec(12));
  } else if (auto* sensor = dynamic_cast<RegionSensor*>(&component)) {
    if (r.hasReal(0)) sensor->moveTo(r.vec(0));
    if (r.hasReal(3)) sensor->turnTo(r.quat(3));
    if (r.hasReal(7)) sensor->resizeBox(r.vec(7));
    if (r.hasReal(10)) sensor->resizeSphere(r.real(10));
  } else if (auto* source = dynamic_cast<ParticleSource*>(&component)) {
    if (r.hasReal(0)) source->setEnabled(r.real(0) != 0.0);
    if (r.hasReal(1)) source->changeRate(r.real(1));
  } else if (auto* sink = dynamic_cast<ParticleSink*>(&component)) {
    if (r.hasReal(0)) sink->setEnabled(r.real(0) != 0.0);
    if (r.hasReal(1)) sink->moveTo(r.vec(1));
  } else if (!p.reals.empty()) {
    throw ArgumentError(kind + " input: this kind takes no reals, got " + std::to_string(p.reals.size()));
  }
}

void writeOutputs(const Component& component, int handle, Package& p) {
  const v1::DataPackage& d = component.outputs();
  p.ints.assign({handle, static_cast<long long>(d.step())});
  p.reals.clear();
  p.strings.assign({component.kind(), component.name()});
  p.string_views.clear();
  switch (d.output_case()) {
    case v1::DataPackage::kSimulationBox: {
      const auto& o = d.simulation_box();
      p.ints.push_back(static_cast<long long>(o.particle_count()));
      p.reals.insert(p.reals.end(), {o.time(), o.total_mass(), o.kinetic_energy(), o.step_rate()});
      break;
    }
    case v1::DataPackage::kRigidBody: {
      const auto& o = d.rigid_body();
      for (const auto* v : {&o.mean_force(), &o.mean_torque(), &o.force(), &o.torque(), &o.position()}) pushVec(p, *v);
      const Quat q = fromProto(o.orientation(), o.has_orientation());
      p.reals.insert(p.reals.end(), {q.w, q.x, q.y, q.z});
      break;
    }
    case v1::DataPackage::kParticleSource:
    case v1::DataPackage::kParticleSink: {
      const auto& o = d.has_particle_source() ? d.particle_source() : d.particle_sink();
      pushCount(p, o.interval());
      pushCount(p, o.total());
      pushCount(p, o.shortfall_total());
      break;
    }
    case v1::DataPackage::kRegionSensor: {
      const auto& o = d.region_sensor();
      p.ints.push_back(static_cast<long long>(o.count()));
      p.ints.push_back(static_cast<long long>(std::min<std::uint64_t>(o.bonds_intact(), LLONG_MAX)));
      p.ints.push_back(static_cast<long long>(std::min<std::uint64_t>(o.bonds_broken(), LLONG_MAX)));
      p.reals.push_back(o.mass());
      // An empty region is sent no centre of mass or mean velocity: zeros here (the unset
      // fields' values), never NaN, which FMI masters and Modelica solvers stop on.
      pushVec(p, o.centre_of_mass());
      pushVec(p, o.mean_velocity());
      break;
    }
    case v1::DataPackage::kFlowSensor: {
      const auto& o = d.flow_sensor();
      for (const auto* v : {&o.positive_interval(), &o.negative_interval(), &o.positive_total(), &o.negative_total()}) {
        pushCount(p, *v);
      }
      break;
    }
    case v1::DataPackage::kParticleView: {
      const auto& o = d.particle_view();
      p.ints.push_back(static_cast<long long>(o.total_count()));
      p.ints.push_back(o.stride());
      for (const auto id : o.ids()) p.ints.push_back(static_cast<long long>(id));
      for (const float x : o.positions()) p.reals.push_back(x);
      for (const float r : o.radii()) p.reals.push_back(r);
      for (const float v : o.velocities()) p.reals.push_back(v);
      break;
    }
    case v1::DataPackage::kDeformableBody: {
      const auto& o = d.deformable_body();
      p.ints.push_back(static_cast<long long>(o.broken_springs()));
      p.ints.push_back(static_cast<long long>(o.node_count()));
      for (const auto node : o.nodes()) p.ints.push_back(node);
      for (const auto* v : {&o.driven_force(), &o.driven_torque(), &o.fixed_force(), &o.fixed_torque()}) pushVec(p, *v);
      p.reals.push_back(o.kinetic_energy());
      p.reals.insert(p.reals.end(), o.displacements().begin(), o.displacements().end());
      break;
    }
    default:
      break;  // no outputs yet (or a kind without any): the header only
  }
}

}  // namespace demlink::client::c_abi

using namespace demlink::client::c_abi;

extern "C" {

dl_package* dl_package_create(void) { return new (std::nothrow) Package(); }

void dl_package_destroy(dl_package* package) { delete asPackage(package); }

int dl_set_data(dl_package* package, const long long* ints, int nInts, const double* reals, int nReals,
                const char* const* strings, int nStrings) {
  Package* p = asPackage(package);
  if (p == nullptr || nInts < 0 || nReals < 0 || nStrings < 0) return DL_ERR_ARGUMENT;
  if ((nInts > 0 && ints == nullptr) || (nReals > 0 && reals == nullptr) || (nStrings > 0 && strings == nullptr)) {
    return DL_ERR_ARGUMENT;
  }
  for (int i = 0; i < nStrings; ++i) {
    if (strings[i] == nullptr) return DL_ERR_ARGUMENT;
  }
  try {
    p->ints.assign(ints, ints + nInts);
    p->reals.assign(reals, reals + nReals);
    p->strings.assign(strings, strings + nStrings);
    p->string_views.clear();
    return DL_OK;
  } catch (...) {
    return DL_ERR_INTERNAL;
  }
}

int dl_get_ints(const dl_package* package, long long* out, int capacity, int* count) {
  const Package* p = asPackage(package);
  return p == nullptr ? DL_ERR_ARGUMENT : copyOut(p->ints, out, capacity, count);
}

int dl_get_reals(const dl_package* package, double* out, int capacity, int* count) {
  const Package* p = asPackage(package);
  return p == nullptr ? DL_ERR_ARGUMENT : copyOut(p->reals, out, capacity, count);
}

int dl_get_strings(const dl_package* package, const char** out, int capacity, int* count) {
  // The pointer array lives in the package so that the returned pointers stay valid.
  const Package* p = asPackage(package);
  if (p == nullptr) return DL_ERR_ARGUMENT;
  try {
    p->string_views.clear();
    for (const auto& s : p->strings) p->string_views.push_back(s.c_str());
  } catch (...) {
    return DL_ERR_INTERNAL;
  }
  return copyOut(p->string_views, out, capacity, count);
}

}  // extern "C"
