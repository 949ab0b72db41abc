#pragma once
/// A scene component that takes part in the time step: particle sources and
/// sinks (stage insert_remove), region and flow sensors, trackers and sinks'
/// tallies (stage observe); stages as in step/stage_table.hpp. The world runs a component only in the stages it declares, and a
/// scene without components runs no component pass at all.
///
/// Why a virtual interface here but compile-time contact laws: components run
/// once per step (a handful of virtual calls), contact laws once per contact.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "demlink/core/step/stage_table.hpp"

namespace demlink::core {

class ComponentWorld;
class StateWriter;
class StateReader;

/// Stages a component takes part in: stageBit(Stage::kInsertRemove) (after mesh
/// motion, before the drift) and stageBit(Stage::kObserve) (last, at the step's end time).
using StageSet = std::uint32_t;
static_assert(kStageCount <= 32, "a StageSet holds one bit per stage");
[[nodiscard]] constexpr StageSet stageBit(Stage stage) { return StageSet{1} << static_cast<unsigned>(stage); }

class WorldComponent {
 public:
  explicit WorldComponent(std::string name) : name_(std::move(name)) {}
  virtual ~WorldComponent() = default;
  WorldComponent(const WorldComponent&) = delete;
  WorldComponent& operator=(const WorldComponent&) = delete;

  /// The scene name of this component (unique within a scene).
  [[nodiscard]] const std::string& name() const { return name_; }
  /// Kind for reports, e.g. "particle_source".
  [[nodiscard]] virtual std::string_view kind() const = 0;
  /// The stages it runs in (insert_remove, observe).
  [[nodiscard]] virtual StageSet stages() const = 0;

  /// Called once by World::initialize(), after materials are mixed and before the
  /// first force evaluation; throw InputError for a reference that does not
  /// resolve (e.g. a mesh body index).
  virtual void initialize(ComponentWorld& /*world*/) {}
  /// Stage insert_remove. `world.time()` is the time at the start of the step.
  virtual void insertAndRemove(ComponentWorld& /*world*/) {}
  /// Stage observe. `world.time()` is the time at the end of the step.
  virtual void observe(const ComponentWorld& /*world*/) {}

  /// The largest speed [m/s] the component gives particles (a source's insertion
  /// speed), for the time-step limit; nullopt: none.
  [[nodiscard]] virtual std::optional<double> largestSpeed(const ComponentWorld& /*world*/) const { return std::nullopt; }

  /// Writes whatever the component's future behaviour depends on (random
  /// generator state, accumulated counts, next insertion time) into a
  /// checkpoint. Default: no state.
  virtual void saveState(StateWriter& /*out*/) const {}
  /// Reads back what saveState wrote, into a component built from the same
  /// scene; throw InputError via in.fail() for inconsistent data. Default: no state.
  virtual void loadState(StateReader& /*in*/) {}

  /// Run-time inputs (a co-simulation client's source on/off and rate, sink on/off and
  /// region, sensor region): true once one was applied. Checkpoints save the inputs of such
  /// components in their own section (INPT), so files of runs without inputs are unchanged.
  [[nodiscard]] virtual bool inputsChanged() const { return false; }
  /// Writes the current run-time input values. Default: none.
  virtual void saveInputs(StateWriter& /*out*/) const {}
  /// Reads back what saveInputs wrote (a component built from the same scene); throws
  /// InputError via in.fail() for inconsistent data. Default: none.
  virtual void loadInputs(StateReader& /*in*/) {}

 private:
  std::string name_;
};

}  // namespace demlink::core
