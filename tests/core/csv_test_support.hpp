#pragma once
/// Reading DEMLink's CSV outputs back in tests: cells split so that empty cells (a value
/// that does not exist, core/output/csv_table.hpp) are kept, trailing ones included
/// (std::getline on ',' would drop those), and a check for non-finite numbers spelled out.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace demlink::core::test {

/// The cells of one line: n commas make n + 1 cells, empty ones included.
inline std::vector<std::string> csvCells(std::string_view line) {
  std::vector<std::string> cells(1);
  for (const char c : line) {
    if (c == ',') {
      cells.emplace_back();
    } else if (c != '\n' && c != '\r') {
      cells.back() += c;
    }
  }
  return cells;
}

/// Every line of a CSV file (the header first) as cells.
inline std::vector<std::vector<std::string>> readCsvRows(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) rows.push_back(csvCells(line));
  return rows;
}

/// True for a cell that spells a NaN or an infinity as strtod would read it ("nan",
/// "-inf", "Infinity", "nan(0x1)", any case), which no DEMLink file may hold.
inline bool spellsNonFinite(std::string_view cell) {
  std::string word;
  for (const char c : cell) {
    if (c != '+' && c != '-' && c != ' ') word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return word == "nan" || word.starts_with("nan(") || word == "inf" || word == "infinity";
}

}  // namespace demlink::core::test
