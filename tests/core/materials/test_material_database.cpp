// The materials database: the shipped file loads, holds the eight materials of
// the coupling paper (sec. 4.2) with valid values, is embedded unchanged, and
// every kind of malformed file is refused with an error naming line and column.
#include <gtest/gtest.h>

#include <ostream>

#include <string>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/materials/material_database.hpp"

namespace demlink::core {
namespace {

const char* const kHeader =
    "name,density,youngs_modulus,poisson_ratio,restitution,sliding_friction,rolling_friction,size_kind,"
    "radius_min,radius_max,source\n";
const char* const kGoodRow = "glass,2500,1e7,0.3,0.5,0.5,0,uniform,0.001,0.002,estimate\n";

/// Parses `text` and returns the InputError (fails the test if none is thrown).
InputError parseError(const std::string& text) {
  try {
    (void)MaterialDatabase::parse(text, "test.csv");
  } catch (const InputError& error) {
    return error;
  }
  ADD_FAILURE() << "expected an InputError for:\n" << text;
  return InputError("(none)", "", "");
}

TEST(MaterialDatabase, BuiltInHoldsThePapersEightMaterials) {
  const MaterialDatabase& db = MaterialDatabase::builtIn();
  for (const char* name : {"gravel", "sand", "hard coal", "brown coal", "iron ore", "potash", "corn", "wheat"}) {
    EXPECT_NE(db.find(name), nullptr) << name;
  }
}

TEST(MaterialDatabase, EveryEntryValidatesAndHasSizeAndSource) {
  const MaterialDatabase& db = MaterialDatabase::builtIn();
  ASSERT_GE(db.records().size(), 8u);
  for (const MaterialRecord& r : db.records()) {
    SCOPED_TRACE(r.material.name);
    EXPECT_NO_THROW(r.material.validate("database." + r.material.name));
    // DEM (reduced) moduli: the file promises 1e6..1e8 Pa.
    EXPECT_GE(r.material.youngs_modulus, 1.0e6);
    EXPECT_LE(r.material.youngs_modulus, 1.0e8);
    EXPECT_GT(r.size.radius_min, 0.0);
    EXPECT_GE(r.size.radius_max, r.size.radius_min);
    EXPECT_FALSE(r.source.empty());
  }
}

TEST(MaterialDatabase, EmbeddedCopyMatchesTheRepositoryFile) {
  const MaterialDatabase file = MaterialDatabase::fromFile(std::string(DEMLINK_SOURCE_DIR) + "/data/materials.csv");
  const MaterialDatabase& embedded = MaterialDatabase::builtIn();
  ASSERT_EQ(file.records().size(), embedded.records().size());
  for (std::size_t k = 0; k < file.records().size(); ++k) {
    const MaterialRecord& a = file.records()[k];
    const MaterialRecord& b = embedded.records()[k];
    EXPECT_EQ(a.material.name, b.material.name);
    EXPECT_EQ(a.material.density, b.material.density);
    EXPECT_EQ(a.material.restitution, b.material.restitution);
    EXPECT_EQ(a.size.radius_max, b.size.radius_max);
    EXPECT_EQ(a.source, b.source);
  }
}

TEST(MaterialDatabase, LookupIgnoresCaseSpacesAndHyphens) {
  const MaterialDatabase& db = MaterialDatabase::builtIn();
  const MaterialRecord* canonical = db.find("iron_ore");
  ASSERT_NE(canonical, nullptr);
  EXPECT_EQ(db.find("Iron Ore"), canonical);
  EXPECT_EQ(db.find("IRON-ORE"), canonical);
  EXPECT_EQ(db.find("ironore"), nullptr);
}

TEST(MaterialDatabase, UnknownNameNamesTheFieldAndListsKnownNames) {
  try {
    (void)MaterialDatabase::builtIn().at("granite", "components[1].material.database_name");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "components[1].material.database_name");
    EXPECT_EQ(e.value(), "\"granite\"");
    const std::string what = e.what();
    for (const std::string& name : MaterialDatabase::builtIn().names()) {
      EXPECT_NE(what.find(name), std::string::npos) << name << " missing from: " << what;
    }
  }
}

TEST(MaterialDatabase, ParsesQuotedFieldsCommentsAndColumnOrder) {
  const MaterialDatabase db = MaterialDatabase::parse(
      "# comment\n\n"
      "source,name,radius_max,radius_min,size_kind,rolling_friction,sliding_friction,restitution,poisson_ratio,"
      "youngs_modulus,density\n"
      "\"Smith, 2020: \"\"calibrated\"\"\",beads,0.003,0.001,Uniform,0.1,0.4,0.7,0.25,2e7,2600\n",
      "inline");
  ASSERT_EQ(db.records().size(), 1u);
  const MaterialRecord& r = db.records()[0];
  EXPECT_EQ(r.material.name, "beads");
  EXPECT_EQ(r.source, "Smith, 2020: \"calibrated\"");
  EXPECT_EQ(r.material.density, 2600.0);
  EXPECT_EQ(r.material.youngs_modulus, 2e7);
  EXPECT_EQ(r.material.restitution, 0.7);
  EXPECT_EQ(r.size.kind, MaterialSizeRange::Kind::Uniform);
  EXPECT_EQ(r.size.radius_min, 0.001);
  EXPECT_EQ(r.size.radius_max, 0.003);
  EXPECT_EQ(r.line, 4u);
}

struct Malformed {
  const char* what;
  std::string text;
  std::string field;  ///< expected InputError::field()
};

void PrintTo(const Malformed& c, std::ostream* os) { *os << c.what; }

class MalformedDatabase : public ::testing::TestWithParam<Malformed> {};

TEST_P(MalformedDatabase, ErrorNamesLineAndColumn) {
  const Malformed& c = GetParam();
  const InputError e = parseError(c.text);
  EXPECT_EQ(e.field(), c.field) << e.what();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MalformedDatabase,
    ::testing::Values(
        Malformed{"missing_column",
                  "# header lacks density\nname,youngs_modulus,poisson_ratio,restitution,sliding_friction,"
                  "rolling_friction,size_kind,radius_min,radius_max,source\n",
                  "test.csv:2.header"},
        Malformed{"unknown_column", std::string("name,colour,") + (kHeader + 5), "test.csv:1.header"},
        Malformed{"non_numeric", std::string(kHeader) + kGoodRow +
                                     "sand,2650,lots,0.3,0.5,0.5,0,uniform,0.001,0.002,estimate\n",
                  "test.csv:3.youngs_modulus"},
        Malformed{"trailing_garbage", std::string(kHeader) + "sand,2650kg,1e7,0.3,0.5,0.5,0,uniform,0.001,0.002,x\n",
                  "test.csv:2.density"},
        Malformed{"negative_density", std::string(kHeader) + "\n\nsand,-2650,1e7,0.3,0.5,0.5,0,uniform,0.001,0.002,x\n",
                  "test.csv:4.density"},
        Malformed{"restitution_above_one",
                  std::string(kHeader) + "sand,2650,1e7,0.3,1.5,0.5,0,uniform,0.001,0.002,x\n",
                  "test.csv:2.restitution"},
        Malformed{"duplicate_name", std::string(kHeader) + kGoodRow + "# again\nGlass,2600,1e7,0.3,0.5,0.5,0,uniform,"
                                                                      "0.001,0.002,estimate\n",
                  "test.csv:4.name"},
        Malformed{"field_count", std::string(kHeader) + "sand,2650,1e7,0.3,0.5,0.5\n", "test.csv:2"},
        Malformed{"size_kind", std::string(kHeader) + "sand,2650,1e7,0.3,0.5,0.5,0,normal,0.001,0.002,x\n",
                  "test.csv:2.size_kind"},
        Malformed{"radii_reversed", std::string(kHeader) + "sand,2650,1e7,0.3,0.5,0.5,0,uniform,0.002,0.001,x\n",
                  "test.csv:2.radius_max"},
        Malformed{"empty_source", std::string(kHeader) + "sand,2650,1e7,0.3,0.5,0.5,0,uniform,0.001,0.002,\n",
                  "test.csv:2.source"},
        Malformed{"unterminated_quote",
                  std::string(kHeader) + "sand,2650,1e7,0.3,0.5,0.5,0,uniform,0.001,0.002,\"open\n", "test.csv:2"},
        Malformed{"empty_file", "# nothing\n", "test.csv"}),
    [](const ::testing::TestParamInfo<Malformed>& param) { return std::string(param.param.what); });

TEST(MaterialDatabase, MissingFileNamesThePath) {
  try {
    (void)MaterialDatabase::fromFile("/nonexistent/materials.csv");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "materials database");
    EXPECT_NE(std::string(e.what()).find("/nonexistent/materials.csv"), std::string::npos) << e.what();
  }
}


TEST(MaterialDatabase, CsvTextReadsBackToTheSameRecords) {
  MaterialRecord record;
  record.material.name = "calibrated sand";
  record.material.density = 2650.0;
  record.material.youngs_modulus = 3.3e7;
  record.material.poisson_ratio = 0.27;
  record.material.restitution = 0.41;
  record.material.sliding_friction = 0.1 + 0.2;  // not short in decimal: the round trip must keep every bit
  record.material.rolling_friction = 0.123456789012345;
  record.material.cohesion_energy_density = 1.5e4;
  record.size = {MaterialSizeRange::Kind::Uniform, 0.00025, 0.001};
  record.source = "calibrated: \"repose\", 32.1 deg";
  MaterialRecord constant = record;
  constant.material.name = "beads";
  constant.size = {MaterialSizeRange::Kind::Constant, 0.002, 0.002};
  const MaterialDatabase back = MaterialDatabase::parse(MaterialDatabase::toCsv({record, constant}), "written.csv");
  ASSERT_EQ(back.records().size(), 2u);
  const MaterialRecord& r = back.records()[0];
  EXPECT_EQ(r.material.name, record.material.name);
  EXPECT_EQ(r.material.density, record.material.density);
  EXPECT_EQ(r.material.youngs_modulus, record.material.youngs_modulus);
  EXPECT_EQ(r.material.poisson_ratio, record.material.poisson_ratio);
  EXPECT_EQ(r.material.restitution, record.material.restitution);
  EXPECT_EQ(r.material.sliding_friction, record.material.sliding_friction);
  EXPECT_EQ(r.material.rolling_friction, record.material.rolling_friction);
  EXPECT_EQ(r.material.cohesion_energy_density, record.material.cohesion_energy_density);
  EXPECT_EQ(r.size.kind, MaterialSizeRange::Kind::Uniform);
  EXPECT_EQ(r.size.radius_min, record.size.radius_min);
  EXPECT_EQ(r.size.radius_max, record.size.radius_max);
  EXPECT_EQ(r.source, record.source);
  EXPECT_EQ(back.records()[1].size.kind, MaterialSizeRange::Kind::Constant);
}

TEST(MaterialDatabase, BuiltInWithAddsAUsersMaterialsAndRefusesABuiltInName) {
  const MaterialDatabase user = MaterialDatabase::parse(std::string(kHeader) + kGoodRow, "mine.csv");
  const MaterialDatabase both = MaterialDatabase::builtInWith(user);
  EXPECT_EQ(both.records().size(), MaterialDatabase::builtIn().records().size() + 1);
  EXPECT_NE(both.find("Glass"), nullptr);
  EXPECT_NE(both.find("wheat"), nullptr);
  const MaterialDatabase clash = MaterialDatabase::parse(
      std::string(kHeader) + kGoodRow + "Hard-Coal,1350,2e7,0.3,0.5,0.5,0.1,uniform,0.005,0.025,mine\n", "mine.csv");
  try {
    (void)MaterialDatabase::builtInWith(clash);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "mine.csv:3.name");
    EXPECT_EQ(e.value(), "\"Hard-Coal\"");
  }
}

}  // namespace
}  // namespace demlink::core
