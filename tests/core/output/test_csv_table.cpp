// The one rule for a numeric CSV cell (core/output/csv_table.hpp): a finite value is its
// shortest round-trip text (read back exactly), NaN (a value that does not exist) is an
// empty cell with the row's column count kept, and an infinity is refused naming the
// file and column, with nothing of the row written.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <unistd.h>
#include <vector>

#include "demlink/core/output/csv_table.hpp"
#include "csv_test_support.hpp"

namespace demlink::core {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(CsvNumber, FiniteReadsBackExactlyNaNIsEmptyInfinityIsRefused) {
  for (const double value : {0.1 + 0.2, -1.0e-300, 4.9e-324, 1.7976931348623157e308, 0.0, -0.0, 3.0}) {
    const std::string text = csvNumber(value);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), value) << text;
    EXPECT_EQ(std::signbit(std::strtod(text.c_str(), nullptr)), std::signbit(value)) << text;
  }
  EXPECT_EQ(csvNumber(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(csvNumber(kNaN), "");
  EXPECT_EQ(csvNumber(-kNaN), "");
  EXPECT_THROW((void)csvNumber(kInf), std::domain_error);
  EXPECT_THROW((void)csvNumber(-kInf), std::domain_error);
}

TEST(CsvTable, MissingValuesAreEmptyCellsAndInfinityIsRefusedWholeRow) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("demlink_csv_table_" + std::to_string(::getpid()) + ".csv");
  {
    CsvTable table(path, {"time_s", "count", "com_x_m", "com_y_m"});
    table.writeRow(std::vector<double>{0.5, 2.0, 0.25, -1.5});
    table.writeRow(std::vector<double>{1.0, 0.0, kNaN, kNaN});
    try {
      table.writeRow(std::vector<double>{1.5, 1.0, 0.5, -kInf});
      ADD_FAILURE() << "an infinite value was written";
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find(path.string() + ": column com_y_m: "), std::string::npos)
          << error.what();
      EXPECT_NE(std::string(error.what()).find("-inf"), std::string::npos) << error.what();
    }
    EXPECT_EQ(table.rowCount(), 2u);
  }
  const auto rows = test::readCsvRows(path);
  ASSERT_EQ(rows.size(), 3u) << "the header and two rows: nothing of the refused row";
  EXPECT_EQ(rows[1], (std::vector<std::string>{"0.5", "2", "0.25", "-1.5"}));
  EXPECT_EQ(rows[2], (std::vector<std::string>{"1", "0", "", ""})) << "four cells, the last two empty";
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace demlink::core
