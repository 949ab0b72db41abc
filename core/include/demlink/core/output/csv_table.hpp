#pragma once
/// A CSV file written one row at a time and flushed after every row, so that a run that
/// stops (or crashes) loses no row already produced.
///
/// Why numbers only: every sensor and tracker column is a quantity; a missing value
/// (an empty region's centre of mass, a removed particle) is written as "nan", which
/// spreadsheets, numpy and pandas all read as not-a-number. Values use the shortest
/// text that reads back to the same double, so files can be compared exactly.
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <vector>

namespace demlink::core {

class CsvTable {
 public:
  /// Creates (truncates) `path` and writes the header line. Column names carry their
  /// unit, e.g. "mass_kg". Throws std::runtime_error if the file cannot be written.
  CsvTable(std::filesystem::path path, const std::vector<std::string>& columns);

  /// Appends one row (as many values as columns) and flushes it. Throws
  /// std::invalid_argument for a wrong value count, std::runtime_error on a write error.
  void writeRow(std::span<const double> values);

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] std::size_t columnCount() const { return columns_; }
  [[nodiscard]] std::size_t rowCount() const { return rows_; }

 private:
  std::filesystem::path path_;
  std::ofstream out_;
  std::size_t columns_ = 0;
  std::size_t rows_ = 0;
};

}  // namespace demlink::core
