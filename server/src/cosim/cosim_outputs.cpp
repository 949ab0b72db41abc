/// Output packages per component kind (contract in cosim_outputs.hpp).
///
/// Definitions: SimulationBox: time, particle count, total mass, kinetic energy
/// (translational + rotational) and step rate = world steps / wall seconds spent stepping
/// since the previous answer. ParticleSource: inserted during the interval and in total,
/// shortfall in total (report()). ParticleSink: removed during the interval and in total.
/// RegionSensor: measure() of the world now. FlowSensor: crossings during the interval and
/// in total. ParticleView: the particles whose id is a multiple of the stride, in id order,
/// stride = ceil(largest id / max_count).
/// RigidBody: the interval's wrench and the server's pose. MassSpringBody / FemBody: the
/// reported nodes' displacements, the reactions and broken springs at the interval's end.
#include "demlink/server/cosim/cosim_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <google/protobuf/message.h>

#include "demlink/core/components/particle_sink.hpp"
#include "demlink/core/deformable/deformable_body.hpp"
#include "demlink/core/components/particle_source.hpp"
#include "demlink/core/components/region_sensor.hpp"
#include "demlink/core/step/watchdog.hpp"
#include "demlink/server/scene/proto_convert.hpp"

namespace demlink::server {
namespace {

void setCount(v1::CountAndMass& out, std::uint64_t count, double mass) {
  out.set_count(count);
  out.set_mass(mass);
}

}  // namespace

std::optional<std::string> firstNonFiniteField(const google::protobuf::Message& message) {
  const google::protobuf::Reflection& reflection = *message.GetReflection();
  std::vector<const google::protobuf::FieldDescriptor*> fields;
  reflection.ListFields(message, &fields);
  using Field = google::protobuf::FieldDescriptor;
  for (const Field* field : fields) {
    const int count = field->is_repeated() ? reflection.FieldSize(message, field) : 1;
    for (int k = 0; k < count; ++k) {
      const std::string name = field->is_repeated() ? field->name() + "[" + std::to_string(k) + "]" : field->name();
      double value = 0.0;
      switch (field->cpp_type()) {
        case Field::CPPTYPE_DOUBLE:
          value = field->is_repeated() ? reflection.GetRepeatedDouble(message, field, k)
                                       : reflection.GetDouble(message, field);
          break;
        case Field::CPPTYPE_FLOAT:
          value = field->is_repeated() ? reflection.GetRepeatedFloat(message, field, k)
                                       : reflection.GetFloat(message, field);
          break;
        case Field::CPPTYPE_MESSAGE: {
          const google::protobuf::Message& inner = field->is_repeated()
                                                       ? reflection.GetRepeatedMessage(message, field, k)
                                                       : reflection.GetMessage(message, field);
          if (std::optional<std::string> bad = firstNonFiniteField(inner)) return name + "." + *bad;
          continue;
        }
        default: continue;
      }
      if (!std::isfinite(value)) return name;
    }
  }
  return std::nullopt;
}

CosimOutputs::CosimOutputs(std::size_t componentCount) : memory_(componentCount) {}

void CosimOutputs::addStepping(std::uint64_t steps, double wallSeconds) {
  for (Memory& m : memory_) {
    m.steps += steps;
    m.wall += wallSeconds;
  }
}

v1::DataPackage CosimOutputs::outputOf(std::size_t index, const CosimComponent& component, const core::World& world,
                                       const core::IntervalWrench& wrench) {
  Memory& memory = memory_.at(index);
  v1::DataPackage out;
  out.set_component_id(component.id);
  out.set_step(world.stepCount());
  switch (component.kind_case) {
    case v1::ComponentDeclaration::kSimulationBox: {
      v1::SimulationBoxOutput& box = *out.mutable_simulation_box();
      box.set_time(world.time());
      box.set_particle_count(world.particles().size());
      box.set_total_mass(world.totalMass());
      box.set_kinetic_energy(world.kineticEnergy());
      box.set_step_rate(memory.wall > 0.0 ? static_cast<double>(memory.steps) / memory.wall : 0.0);
      memory.steps = 0;
      memory.wall = 0.0;
      break;
    }
    case v1::ComponentDeclaration::kRigidBody: {
      v1::RigidBodyOutput& body = *out.mutable_rigid_body();
      setVec3(*body.mutable_mean_force(), wrench.mean_force);
      setVec3(*body.mutable_mean_torque(), wrench.mean_torque);
      setVec3(*body.mutable_force(), wrench.force);
      setVec3(*body.mutable_torque(), wrench.torque);
      if (component.mesh) {
        const core::MeshBody& mesh = world.meshes()[*component.mesh];
        setVec3(*body.mutable_position(), mesh.position());
        setQuat(*body.mutable_orientation(), mesh.orientation());
      }
      break;
    }
    case v1::ComponentDeclaration::kParticleSource: {
      const auto* source = dynamic_cast<const core::ParticleSource*>(component.engine);
      if (source == nullptr) break;
      const core::SourceReport& report = source->report();
      v1::SourceSinkOutput& o = *out.mutable_particle_source();
      setCount(*o.mutable_interval(), report.inserted_count - memory.count, report.inserted_mass - memory.mass);
      setCount(*o.mutable_total(), report.inserted_count, report.inserted_mass);
      setCount(*o.mutable_shortfall_total(), report.shortfall_count, report.shortfall_mass);
      memory.count = report.inserted_count;
      memory.mass = report.inserted_mass;
      break;
    }
    case v1::ComponentDeclaration::kParticleSink: {
      const auto* sink = dynamic_cast<const core::ParticleSink*>(component.engine);
      if (sink == nullptr) break;
      const core::RemovalTally& total = sink->total();
      v1::SourceSinkOutput& o = *out.mutable_particle_sink();
      setCount(*o.mutable_interval(), total.count - memory.count, total.mass - memory.mass);
      setCount(*o.mutable_total(), total.count, total.mass);
      memory.count = total.count;
      memory.mass = total.mass;
      break;
    }
    case v1::ComponentDeclaration::kRegionSensor: {
      const auto* sensor = dynamic_cast<const core::RegionSensor*>(component.engine);
      if (sensor == nullptr) break;
      const core::RegionReading reading = sensor->measure(world);
      v1::RegionSensorOutput& o = *out.mutable_region_sensor();
      o.set_count(reading.count);
      o.set_mass(reading.mass);
      o.set_bonds_intact(reading.bonds_intact);
      o.set_bonds_broken(reading.bonds_broken);
      if (reading.count > 0) {  // an empty region has no centre of mass: left unset, never NaN
        setVec3(*o.mutable_centre_of_mass(), reading.centre_of_mass);
        setVec3(*o.mutable_mean_velocity(), reading.mean_velocity);
      }
      break;
    }
    case v1::ComponentDeclaration::kFlowSensor: {
      const auto* sensor = dynamic_cast<const core::FlowSensor*>(component.engine);
      if (sensor == nullptr) break;
      const core::FlowTally& total = sensor->total();
      v1::FlowSensorOutput& o = *out.mutable_flow_sensor();
      setCount(*o.mutable_positive_interval(), total.positive_count - memory.flow.positive_count,
               total.positive_mass - memory.flow.positive_mass);
      setCount(*o.mutable_negative_interval(), total.negative_count - memory.flow.negative_count,
               total.negative_mass - memory.flow.negative_mass);
      setCount(*o.mutable_positive_total(), total.positive_count, total.positive_mass);
      setCount(*o.mutable_negative_total(), total.negative_count, total.negative_mass);
      memory.flow = total;
      break;
    }
    case v1::ComponentDeclaration::kMassSpringBody:
    case v1::ComponentDeclaration::kFemBody: {
      if (!component.deformable) break;
      const core::DeformableBody& body = *world.deformableBodies()[*component.deformable];
      v1::DeformableBodyOutput& o = *out.mutable_deformable_body();
      for (const std::uint32_t node : component.output_nodes) {
        o.add_nodes(node);
        const core::Vec3 u = body.nodeDisplacement(node);
        for (int k = 0; k < 3; ++k) o.add_displacements(u[k]);
      }
      const core::NodeReaction driven = body.drivenReaction();
      const core::NodeReaction fixed = body.fixedReaction();
      setVec3(*o.mutable_driven_force(), driven.force);
      setVec3(*o.mutable_driven_torque(), driven.torque);
      setVec3(*o.mutable_fixed_force(), fixed.force);
      setVec3(*o.mutable_fixed_torque(), fixed.torque);
      o.set_broken_springs(body.brokenCount());
      o.set_kinetic_energy(body.kineticEnergy());
      o.set_node_count(body.nodeCount());
      break;
    }
    case v1::ComponentDeclaration::kParticleView: {
      // Decimated by id, not by slot: the engine re-sorts slots, ids stay. At most
      // largest id / stride <= max_count ids are multiples of the stride.
      const core::ParticleArrays& p = world.particles();
      const std::size_t n = p.size();
      const std::uint64_t maxCount = std::max<std::uint64_t>(1, component.view_max_count);
      const std::uint64_t largestId = n == 0 ? 0 : *std::max_element(p.id.begin(), p.id.end());
      const std::uint64_t stride = std::max<std::uint64_t>(1, (largestId + maxCount - 1) / maxCount);
      std::vector<std::pair<std::uint64_t, std::size_t>> listed;  // (id, slot)
      for (std::size_t i = 0; i < n; ++i) {
        if (p.id[i] % stride == 0) listed.emplace_back(p.id[i], i);
      }
      std::sort(listed.begin(), listed.end());
      v1::ParticleViewOutput& o = *out.mutable_particle_view();
      o.set_total_count(n);
      o.set_stride(static_cast<std::uint32_t>(std::min<std::uint64_t>(stride, UINT32_MAX)));
      for (const auto& [id, i] : listed) {
        for (int k = 0; k < 3; ++k) o.add_positions(static_cast<float>(p.position[i][k]));
        for (int k = 0; k < 3; ++k) o.add_velocities(static_cast<float>(p.velocity[i][k]));
        o.add_radii(static_cast<float>(p.radius[i]));
        o.add_ids(id);
      }
      break;
    }
    default: break;
  }
  // Never hand a client a NaN: a non-finite output ends the simulation (the host
  // sends Error{SIMULATION_FAULT} to every client instead).
  if (const std::optional<std::string> field = firstNonFiniteField(out)) {
    throw core::SimulationFault("non_finite_output", "output " + *field + " of component " + component.name +
                                                         " is not finite",
                                world.stepCount());
  }
  return out;
}

}  // namespace demlink::server
