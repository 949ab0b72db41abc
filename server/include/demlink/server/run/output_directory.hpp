#pragma once
/// Where a run may write: the policy that keeps one run from overwriting another's results.
///
/// - A headless run's folder (and a co-simulation's, when the host is told to overwrite)
///   must be missing or empty, unless RunOptions::overwrite: then files of the same name
///   are overwritten in place and other files of the earlier run stay.
/// - A co-simulation host numbers its folders sim_001, sim_002, ... under its output root
///   and never reuses one that exists, so a restarted server (numbering starts again at
///   1) or a second server on the same root goes on after the highest folder present.
///
/// Why refuse rather than clear the folder: the folder is the user's choice (it may be ".");
/// deleting files there is not ours to decide.
#include <cstdint>
#include <filesystem>
#include <string>

namespace demlink::server {

/// Checks the policy for `directory` and creates it. Throws core::InputError naming
/// `field` and the folder when it is not empty and `overwrite` is false (saying to use
/// --overwrite), or when it cannot be created.
void claimOutputDirectory(const std::filesystem::path& directory, bool overwrite, const std::string& field);

/// The next co-simulation folder: creates root/sim_NNN (simulationDirectory) for the
/// smallest N >= `first` whose folder does not exist yet and returns N. The folder is
/// created here, so two servers on one root cannot both take it. Throws
/// std::runtime_error if root cannot be written.
[[nodiscard]] std::uint64_t claimSimulationDirectory(const std::filesystem::path& root, std::uint64_t first);

/// root/sim_NNN for simulation `number` (the folder is not created).
[[nodiscard]] std::filesystem::path simulationDirectory(const std::filesystem::path& root, std::uint64_t number);

}  // namespace demlink::server
