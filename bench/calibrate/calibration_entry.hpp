#pragma once
/// The result of a calibration as a materials-file entry: the base material's row with the
/// fitted values and its own name, written in the format of data/materials.csv so that a
/// scene loads it with simulation_box.materials_file (docs/materials.md).
#include <filesystem>
#include <string>
#include <vector>

#include "calibration_targets.hpp"

namespace demlink::calibrate {

/// The base material with `values` (in the order of targets.fit) set, named targets.name;
/// the source says where it came from.
[[nodiscard]] core::MaterialRecord calibratedRecord(const Targets& targets, const std::vector<double>& values);

/// Writes `record` as a materials file, `report` first as '#' comment lines. Throws
/// core::InputError naming `field` when the file cannot be written.
void writeMaterialsFile(const std::filesystem::path& path, const core::MaterialRecord& record,
                        const std::string& report, const std::string& field = "--out");

}  // namespace demlink::calibrate
