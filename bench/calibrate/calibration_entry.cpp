#include "calibration_entry.hpp"

#include <fstream>
#include <sstream>

#include "demlink/core/base/input_error.hpp"

namespace demlink::calibrate {

core::MaterialRecord calibratedRecord(const Targets& targets, const std::vector<double>& values) {
  core::MaterialRecord record = targets.base;
  record.material.name = targets.name;
  std::string fitted;
  for (std::size_t j = 0; j < targets.fit.size(); ++j) {
    setParameter(record.material, targets.fit[j].parameter, values[j]);
    std::ostringstream value;
    value << parameterName(targets.fit[j].parameter) << " " << values[j];
    fitted += (j > 0 ? ", " : "") + value.str();
  }
  record.source = "calibrated by demlink-calibrate from " + targets.file.filename().string() + " (base " +
                  targets.base.material.name + "): " + fitted;
  return record;
}

void writeMaterialsFile(const std::filesystem::path& path, const core::MaterialRecord& record,
                        const std::string& report, const std::string& field) {
  std::ofstream out(path);
  std::istringstream lines(report);
  for (std::string line; std::getline(lines, line);) out << "# " << line << "\n";
  out << core::MaterialDatabase::toCsv({record});
  out.close();
  if (!out) throw core::InputError(field, path.string(), "cannot be written");
}

}  // namespace demlink::calibrate
