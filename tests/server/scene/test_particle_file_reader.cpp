/// Particle text files ("id x y z r"): the gen_init.py format, and an error naming
/// the line for every kind of malformed line.
#include <gtest/gtest.h>

#include "demlink/core/base/input_error.hpp"
#include "demlink/server/scene/particle_file_reader.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

/// Parses `text` and returns the InputError (fails the test if none is thrown).
core::InputError parseError(const std::string& text) {
  try {
    (void)parseParticleText(text, "init.txt");
  } catch (const core::InputError& error) {
    return error;
  }
  ADD_FAILURE() << "expected an InputError for:\n" << text;
  return core::InputError("(none)", "", "");
}

constexpr const char* kHeader = "# id x y z r   (N=3, seed=12345, density=2500.0, zhi=0.023500)\n";

TEST(ParticleFileReader, ReadsTheGenInitFormat) {
  const std::string text = std::string(kHeader) +
                           "1 4.512345678e-03 4.487654321e-03 3.500000000e-03 2.345678901e-03\n"
                           "2 1.101234567e-02 4.400000000e-03 3.500000000e-03 2.999999999e-03\n"
                           "3 1.749000000e-02 4.600000000e-03 1.000000000e-02 2.000000001e-03\n";
  const std::vector<ParticleRecord> records = parseParticleText(text, "init.txt");
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(records[0].id, 1u);
  EXPECT_EQ(records[0].position, core::Vec3(4.512345678e-03, 4.487654321e-03, 3.5e-03));
  EXPECT_EQ(records[0].radius, 2.345678901e-03);
  EXPECT_EQ(records[0].line, 2u);
  EXPECT_EQ(records[2].id, 3u);
  EXPECT_EQ(records[2].position.z(), 1.0e-02);
}

TEST(ParticleFileReader, IgnoresBlankLinesTrailingCommentsAndCarriageReturns) {
  const std::vector<ParticleRecord> records =
      parseParticleText("\n   \n7\t0.1 0.2 0.3 0.01  # first\r\n# 8 1 1 1 1\n\t9 -1 -2 -3 1e-3\r\n", "f");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].id, 7u);
  EXPECT_EQ(records[0].line, 3u);
  EXPECT_EQ(records[1].id, 9u);
  EXPECT_EQ(records[1].position, core::Vec3(-1, -2, -3));
  EXPECT_EQ(records[1].line, 5u);
}

TEST(ParticleFileReader, NonNumericValueNamesTheLine) {
  const core::InputError error = parseError(std::string(kHeader) + "1 0.1 0.2 0.3 0.01\n2 0.1 abc 0.3 0.01\n");
  EXPECT_EQ(error.field(), "init.txt:line 3");
  EXPECT_EQ(error.value(), "column 3 (y)") << "the place, never the file's text";
  EXPECT_EQ(std::string(error.what()).find("abc"), std::string::npos) << error.what();
}

TEST(ParticleFileReader, TrailingGarbageInANumberIsAnError) {
  EXPECT_EQ(parseError("1 0.1 0.2 0.3x 0.01\n").field(), "init.txt:line 1");
  EXPECT_EQ(parseError("1 0.1 0.2 0.3 0.01,\n").field(), "init.txt:line 1");
}

TEST(ParticleFileReader, NanAndInfinityNameTheLine) {
  const core::InputError nan = parseError("1 0.1 0.2 0.3 0.01\n\n2 nan 0.2 0.3 0.01\n");
  EXPECT_EQ(nan.field(), "init.txt:line 3");
  EXPECT_NE(std::string(nan.what()).find("finite"), std::string::npos) << nan.what();
  EXPECT_EQ(parseError("1 0.1 0.2 inf 0.01\n").field(), "init.txt:line 1");
  EXPECT_EQ(parseError("1 0.1 0.2 0.3 NaN\n").field(), "init.txt:line 1");
  EXPECT_EQ(parseError("1 0.1 0.2 1e999 0.01\n").field(), "init.txt:line 1");
}

TEST(ParticleFileReader, NonPositiveRadiusNamesTheLine) {
  const core::InputError zero = parseError("1 0.1 0.2 0.3 0.01\n2 0.1 0.2 0.3 0\n");
  EXPECT_EQ(zero.field(), "init.txt:line 2");
  EXPECT_NE(std::string(zero.what()).find("column 5 (r): must be > 0"), std::string::npos) << zero.what();
  EXPECT_EQ(parseError("# c\n1 0.1 0.2 0.3 -0.002\n").field(), "init.txt:line 2");
}

TEST(ParticleFileReader, WrongColumnCountNamesTheLine) {
  const core::InputError few = parseError("1 0.1 0.2 0.3 0.01\n2 0.1 0.2 0.3\n");
  EXPECT_EQ(few.field(), "init.txt:line 2");
  EXPECT_EQ(few.value(), "4 columns");
  EXPECT_EQ(parseError("1 0.1 0.2 0.3 0.01 2500\n").field(), "init.txt:line 1");
}

TEST(ParticleFileReader, BadOrRepeatedIdNamesTheLine) {
  EXPECT_EQ(parseError("1.5 0.1 0.2 0.3 0.01\n").field(), "init.txt:line 1");
  EXPECT_EQ(parseError("-1 0.1 0.2 0.3 0.01\n").field(), "init.txt:line 1");
  const core::InputError repeated = parseError("4 0.1 0.2 0.3 0.01\n4 0.2 0.2 0.3 0.01\n");
  EXPECT_EQ(repeated.field(), "init.txt:line 2");
  EXPECT_NE(std::string(repeated.what()).find("line 1"), std::string::npos) << repeated.what();
}

TEST(ParticleFileReader, EmptyOrMissingFileIsAnError) {
  EXPECT_EQ(parseError("# only a comment\n\n").field(), "init.txt");
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  EXPECT_THROW((void)readParticleFile((dir / "missing.txt").string()), core::InputError);
  test::writeText(dir / "ok.txt", "1 0 0 0 1\n");
  EXPECT_EQ(readParticleFile((dir / "ok.txt").string()).size(), 1u);
}

}  // namespace
}  // namespace demlink::server
