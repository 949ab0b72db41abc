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
#include <string>

#include "demlink/core/components/random.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/world.hpp"

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

/// The sub-section `tag` of a component's state, named "<component section>.<name>"
/// in errors.
StateReader componentSection(StateReader& in, std::string_view tag, const std::string& name);

}  // namespace demlink::core
