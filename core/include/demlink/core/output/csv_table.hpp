#pragma once
/// A CSV file written one row at a time and flushed after every row, so that a run that
/// stops (or crashes) loses no row already produced; and the rule for the text of one
/// numeric cell, which every CSV output of DEMLink uses.
///
/// Why numbers only: every sensor and tracker column is a quantity. A value that does not
/// exist (an empty region's centre of mass, a removed particle, a quantity not yet
/// sampled) is NaN in memory and an EMPTY cell on disk, which pandas, numpy.genfromtxt
/// and spreadsheets all read as missing; no file ever holds the text "nan". An infinity
/// is never a reading of a finite world (the watchdog stops a run whose state is not
/// finite), so it is refused rather than written. Values use the shortest text that
/// reads back to the same double, so files can be compared exactly.
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <vector>

namespace demlink::core {

/// Appends the text of one numeric cell to `line`: nothing for NaN (a missing value),
/// the shortest round-trip form of a finite value. Throws std::domain_error for ±inf.
void appendCsvNumber(std::string& line, double value);
/// The text of one numeric cell (appendCsvNumber into an empty string).
[[nodiscard]] std::string csvNumber(double value);

class CsvTable {
 public:
  /// Creates (truncates) `path` and writes the header line. Column names carry their
  /// unit, e.g. "mass_kg". Throws std::runtime_error if the file cannot be written.
  CsvTable(std::filesystem::path path, const std::vector<std::string>& columns);

  /// Appends one row (as many values as columns; NaN is an empty cell) and flushes it.
  /// Throws std::invalid_argument for a wrong value count or an infinite value (naming
  /// the file and column; nothing of the row is written), std::runtime_error on a write
  /// error.
  void writeRow(std::span<const double> values);

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] std::size_t columnCount() const { return columns_.size(); }
  [[nodiscard]] std::size_t rowCount() const { return rows_; }

 private:
  std::filesystem::path path_;
  std::ofstream out_;
  std::vector<std::string> columns_;
  std::size_t rows_ = 0;
};

}  // namespace demlink::core
