/// CSV output of sensors and trackers, and the text of a numeric cell (contract in
/// csv_table.hpp).
///
/// Numbers are formatted with std::to_chars (shortest round-trip form), which is
/// locale-independent, so a decimal comma in the user's locale cannot break a file.
#include "demlink/core/output/csv_table.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace demlink::core {

void appendCsvNumber(std::string& line, double value) {
  if (std::isnan(value)) return;  // a missing value is an empty cell
  if (std::isinf(value)) {
    throw std::domain_error(std::string("an infinite value (") + (value > 0.0 ? "+" : "-") +
                            "inf) has no CSV cell: only finite numbers or a missing value are written");
  }
  char buffer[32];
  const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof buffer, value);
  line.append(buffer, result.ptr);
}

std::string csvNumber(double value) {
  std::string text;
  appendCsvNumber(text, value);
  return text;
}

CsvTable::CsvTable(std::filesystem::path path, const std::vector<std::string>& columns)
    : path_(std::move(path)), out_(path_, std::ios::trunc), columns_(columns) {
  if (!out_) throw std::runtime_error("cannot write " + path_.string());
  std::string header;
  for (const std::string& column : columns) header += (header.empty() ? "" : ",") + column;
  out_ << header << '\n';
  out_.flush();
  if (!out_) throw std::runtime_error("cannot write " + path_.string());
}

void CsvTable::writeRow(std::span<const double> values) {
  if (values.size() != columns_.size()) {
    throw std::invalid_argument(path_.string() + ": row of " + std::to_string(values.size()) + " values for " +
                                std::to_string(columns_.size()) + " columns");
  }
  std::string line;
  line.reserve(24 * values.size());
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k > 0) line += ',';
    try {
      appendCsvNumber(line, values[k]);
    } catch (const std::domain_error& error) {
      throw std::invalid_argument(path_.string() + ": column " + columns_[k] + ": " + error.what());
    }
  }
  line += '\n';
  out_ << line;
  out_.flush();
  if (!out_) throw std::runtime_error("cannot write " + path_.string());
  ++rows_;
}

}  // namespace demlink::core
