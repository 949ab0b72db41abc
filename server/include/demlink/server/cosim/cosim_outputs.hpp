#pragma once
/// The outputs each component kind returns (docs/cosim.md, "Outputs"), built from the world
/// at the step an interval ends.
///
/// Why a memory per component: the engine keeps totals since step 0 (inserted, removed,
/// crossings); "during the interval" is the total now minus the total at the component's
/// previous answer, so it covers exactly the component's own interval whatever the other
/// components' intervals are and whatever the sensors' own CSV schedule is.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "demlink/core/walls/coupled_motion.hpp"
#include "demlink/core/components/flow_sensor.hpp"
#include "demlink/core/world.hpp"
#include "demlink/server/cosim/cosim_compiler.hpp"
#include "demlink/v1/protocol.pb.h"

namespace demlink::server {

/// Path of the first NaN or infinite double/float field of `message` (nested
/// messages and repeated fields included, e.g. "rigid_body.mean_force.x"), if any.
[[nodiscard]] std::optional<std::string> firstNonFiniteField(const google::protobuf::Message& message);

class CosimOutputs {
 public:
  /// One memory per component of `components` (same indices).
  explicit CosimOutputs(std::size_t componentCount);

  /// Adds world steps and the wall time spent stepping [s], for the step rate.
  void addStepping(std::uint64_t steps, double wallSeconds);

  /// The output package of component `index` for its interval ending now (world.stepCount()),
  /// and remembers the totals for its next interval. `wrench` is the rigid body's interval
  /// wrench (ignored for other kinds).
  [[nodiscard]] v1::DataPackage outputOf(std::size_t index, const CosimComponent& component,
                                         const core::World& world, const core::IntervalWrench& wrench);

 private:
  struct Memory {
    std::uint64_t count = 0;  ///< source/sink total at the previous answer [-]
    double mass = 0.0;        ///< [kg]
    core::FlowTally flow;     ///< flow sensor total at the previous answer
    std::uint64_t steps = 0;  ///< simulation box: world steps since the previous answer
    double wall = 0.0;        ///< [s]
  };
  std::vector<Memory> memory_;
};

}  // namespace demlink::server
