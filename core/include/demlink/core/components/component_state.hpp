#pragma once
/// Helpers for the checkpoint state of scene components (sources, sinks, sensors,
/// trackers): the generator state, removal tallies and checked reads of counts and
/// masses.
///
/// Why checked reads: a checkpoint may be corrupt or hand-edited, and a component
/// that loads a NaN mass or an all-zero generator state would go on silently wrong.
/// Every helper reports through StateReader::fail, so the error names the file and
/// the component's section.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "demlink/core/base/random.hpp"
#include "demlink/core/regions/region_shape.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/components/world_component.hpp"
#include "demlink/core/world_state.hpp"

namespace demlink::core {

/// Writes the four state words, the spare normal variate and its flag.
void writeRandomState(StateWriter& out, const Random& rng);
/// Reads what writeRandomState wrote; rejects an all-zero state, a flag other than
/// 0/1 and a non-finite spare.
RandomState readRandomState(StateReader& in);

/// A boolean stored as one byte; anything but 0 or 1 is rejected.
bool readFlag(StateReader& in, const std::string& what);
/// A double that must be finite and >= 0 (a mass, a band width).
double readNonNegative(StateReader& in, const std::string& what);
/// A double that must be finite (a time, a coordinate).
double readFinite(StateReader& in, const std::string& what);
/// A vector whose three components must be finite.
Vec3 readFiniteVector(StateReader& in, const std::string& what);

void writeRemovalTally(StateWriter& out, const RemovalTally& tally);
/// Count, then a finite mass >= 0 [kg].
RemovalTally readRemovalTally(StateReader& in, const std::string& what);

/// A region changed at run time: the shape's kind, its box sides or sphere radius [m], the
/// placement's centre [m] and orientation (velocity and attachment stay the scene's).
void writeRegionInputs(StateWriter& out, const VolumeShape& shape, const RegionPlacement& placement);
/// Reads what writeRegionInputs wrote; the kind must be the scene's, sizes positive, the
/// centre finite and the orientation a unit quaternion. Changes nothing on failure.
void readRegionInputs(StateReader& in, VolumeShape& shape, RegionPlacement& placement);

/// Checkpoint payload of section COMP: the component count, then per component its
/// name, kind and a DATA sub-section written by WorldComponent::saveState.
void saveComponents(StateWriter& out, const std::vector<std::unique_ptr<WorldComponent>>& components);
/// Reads the framing saveComponents wrote and checks count, names and kinds against
/// `components` (the scene's). Returns each component's DATA section, not yet loaded,
/// so the caller can check the rest of the file first.
[[nodiscard]] std::vector<StateReader> readComponentSections(
    StateReader& in, const std::vector<std::unique_ptr<WorldComponent>>& components);
/// Loads every component from its DATA section (which must be read to its end).
/// If one refuses its data, every component gets back the state it had and the
/// error is rethrown, so a failed restore changes no component.
/// `inputs` (empty, or one entry per component) holds the run-time inputs of section INPT,
/// loaded after each component's state and rolled back with it.
void restoreComponents(const std::vector<std::unique_ptr<WorldComponent>>& components,
                       std::vector<StateReader>& data, const std::string& source,
                       std::vector<std::optional<StateReader>>* inputs = nullptr);

/// Whether any component has run-time inputs to save (section INPT is written then only).
[[nodiscard]] bool anyInputsChanged(const std::vector<std::unique_ptr<WorldComponent>>& components);
/// Checkpoint payload of section INPT: the count of components with inputs, then per
/// component its name and a DATA sub-section written by WorldComponent::saveInputs.
void saveComponentInputs(StateWriter& out, const std::vector<std::unique_ptr<WorldComponent>>& components);
/// Reads the framing saveComponentInputs wrote: one entry per scene component, set for
/// those listed; an unknown or repeated name is an error.
[[nodiscard]] std::vector<std::optional<StateReader>> readComponentInputs(
    StateReader& in, const std::vector<std::unique_ptr<WorldComponent>>& components);

/// The sub-section `tag` of a component's state, named "<component section>.<name>"
/// in errors.
StateReader componentSection(StateReader& in, std::string_view tag, const std::string& name);

}  // namespace demlink::core
