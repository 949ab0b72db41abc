/// CSV output of sensors and trackers (contract in csv_table.hpp).
///
/// Numbers are formatted with std::to_chars (shortest round-trip form), which is
/// locale-independent, so a decimal comma in the user's locale cannot break a file.
#include "demlink/core/output/csv_table.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace demlink::core {

CsvTable::CsvTable(std::filesystem::path path, const std::vector<std::string>& columns)
    : path_(std::move(path)), out_(path_, std::ios::trunc), columns_(columns.size()) {
  if (!out_) throw std::runtime_error("cannot write " + path_.string());
  std::string header;
  for (const std::string& column : columns) header += (header.empty() ? "" : ",") + column;
  out_ << header << '\n';
  out_.flush();
  if (!out_) throw std::runtime_error("cannot write " + path_.string());
}

void CsvTable::writeRow(std::span<const double> values) {
  if (values.size() != columns_) {
    throw std::invalid_argument(path_.string() + ": row of " + std::to_string(values.size()) + " values for " +
                                std::to_string(columns_) + " columns");
  }
  std::string line;
  line.reserve(24 * values.size());
  char buffer[32];
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k > 0) line += ',';
    if (std::isnan(values[k])) {
      line += "nan";
      continue;
    }
    const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof buffer, values[k]);
    line.append(buffer, result.ptr);
  }
  line += '\n';
  out_ << line;
  out_.flush();
  if (!out_) throw std::runtime_error("cannot write " + path_.string());
  ++rows_;
}

}  // namespace demlink::core
