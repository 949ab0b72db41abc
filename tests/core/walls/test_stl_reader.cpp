/// Tests for STL reading/writing: round trips, format detection, vertex merging, error
/// reporting (field names with line numbers), degenerate triangles and garbage input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::core {
namespace {

namespace fs = std::filesystem;
using Triangles = std::vector<std::array<std::uint32_t, 3>>;

class StlFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("demlink_stl_" + std::to_string(std::random_device{}()) + "_" + info->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string writeText(const std::string& name, const std::string& content) const {
    std::ofstream(path(name), std::ios::binary) << content;
    return path(name);
  }
  static std::string readBytes(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream os;
    os << in.rdbuf();
    return os.str();
  }
  /// Expects readStl(p) to throw InputError with exactly this field.
  static InputError expectError(const std::string& p, const std::string& field) {
    try {
      (void)readStl(p);
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
      return e;
    }
    ADD_FAILURE() << "expected InputError for " << p;
    return InputError("", "", "");
  }

  fs::path dir_;
};

/// Checks that every triangle of `mesh` has the coordinates of the same-numbered triangle of
/// (vertices, triangles) (the reader keeps triangle order).
void expectSameGeometry(const StlMesh& mesh, const std::vector<Vec3>& vertices,
                        const Triangles& triangles) {
  ASSERT_EQ(mesh.triangles.size(), triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(mesh.vertices[mesh.triangles[t][k]], vertices[triangles[t][k]]) << "tri " << t;
    }
  }
}

TEST_F(StlFiles, AsciiRoundTripMergesVerticesAndIsExact) {
  // Non-representable decimals test the 17-digit output; the box shares each corner between
  // 4 to 6 triangles, so 36 facet corners must merge back into 8 vertices.
  TriangleMesh box = axisAlignedBoxMesh(Vec3(0.1, -1.0 / 3.0, 2e-7), Vec3(0.7, 1e3 / 7.0, 0.3));
  writeStlAscii(path("box.stl"), box.vertices, box.triangles, "my box");
  const StlMesh mesh = readStl(path("box.stl"));
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_TRUE(mesh.warnings.empty());
  expectSameGeometry(mesh, box.vertices, box.triangles);
}

/// double -> float -> double. The volatile store is deliberate: GCC 12.2's SLP vectoriser
/// (-O2 and above) was observed to drop the float rounding of a pair of adjacent
/// static_cast<float> conversions that are widened straight back to double.
double roundToFloat(double x) {
  volatile float f = static_cast<float>(x);
  return f;
}

TEST_F(StlFiles, BinaryRoundTripMergesVerticesToFloatPrecision) {
  const TriangleMesh flat = rectangleMesh(Vec3(0.1, 0.2, 0.3), 1.0, 2.0, 3, 4);
  writeStlBinary(path("flat.stl"), flat.vertices, flat.triangles);
  EXPECT_EQ(fs::file_size(path("flat.stl")), 84u + 50u * flat.triangles.size());
  const StlMesh mesh = readStl(path("flat.stl"));
  EXPECT_EQ(mesh.vertices.size(), flat.vertices.size());
  ASSERT_EQ(mesh.triangles.size(), flat.triangles.size());
  for (std::size_t t = 0; t < flat.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Vec3& v = flat.vertices[flat.triangles[t][k]];
      const Vec3 asFloat(roundToFloat(v.x()), roundToFloat(v.y()), roundToFloat(v.z()));
      EXPECT_EQ(mesh.vertices[mesh.triangles[t][k]], asFloat);
    }
  }
}

TEST_F(StlFiles, BinaryFileStartingWithSolidIsReadAsBinary) {
  const TriangleMesh box = axisAlignedBoxMesh(Vec3(0, 0, 0), Vec3(1, 2, 3));
  writeStlBinary(path("b.stl"), box.vertices, box.triangles);
  std::string bytes = readBytes(path("b.stl"));
  const char header[] = "solid exported by a CAD tool";
  std::memcpy(bytes.data(), header, sizeof header - 1);
  writeText("b.stl", bytes);
  const StlMesh mesh = readStl(path("b.stl"));
  EXPECT_EQ(mesh.vertices.size(), 8u);
  expectSameGeometry(mesh, box.vertices, box.triangles);
}

TEST_F(StlFiles, TruncatedBinaryIsRejected) {
  const TriangleMesh box = axisAlignedBoxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  writeStlBinary(path("t.stl"), box.vertices, box.triangles);
  std::string bytes = readBytes(path("t.stl"));
  writeText("t.stl", bytes.substr(0, bytes.size() - 7));
  const InputError e = expectError(path("t.stl"), "stl:" + path("t.stl"));
  EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  EXPECT_EQ(e.value(), std::to_string(bytes.size() - 7) + " bytes");
  // Same with a "solid" header: must still be diagnosed as binary, not as bad ASCII.
  std::memcpy(bytes.data(), "solid x", 7);
  writeText("t2.stl", bytes.substr(0, 84 + 50 * 3 + 20));
  const InputError e2 = expectError(path("t2.stl"), "stl:" + path("t2.stl"));
  EXPECT_NE(std::string(e2.what()).find("truncated"), std::string::npos) << e2.what();
}

const char* const kFacet =
    "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n"
    "      vertex 0 1 0\n    endloop\n  endfacet\n";

TEST_F(StlFiles, MalformedAsciiReportsLineNumbers) {
  struct Case {
    std::string content;
    int line;
    std::string value;   // offending token (reported by its length)
    std::string reason;  // substring of the message
  };
  const std::string head = std::string("solid t\n") + kFacet;             // lines 1..8
  const std::string open = head + "  facet normal 0 0 1\n outer loop\n";  // lines 9, 10
  const Case cases[] = {
      {head + "  facett normal 0 0 1\n", 9, "facett", "expected keyword 'facet'"},
      {open + " vertex 0 0 0\n vertex 1 0 0\n endloop\n", 13, "endloop", "has 2 vertices"},
      {open + " vertex 0 0 0\n vertex 1 0 0\n vertex 0 1 0\n vertex 1 1 0\n endloop\n", 14,
       "vertex", "more than 3 vertices"},
      {open + " vertex 0 abc 0\n", 11, "abc", "expected a number"},
      {open + " vertex 0 1.5x 0\n", 11, "1.5x", "expected a number"},
      {open + " vertex 0 0\n endloop\n", 12, "endloop", "expected a number"},
      {open + " vertex 0 0 0\n", 12, "<end of file>", "expected keyword 'vertex'"},
      {open + " vertex 0 0 0\n vertex 1 0 0\n vertex 0 1 0\n endfacet\n", 14, "endfacet",
       "expected keyword 'endloop'"},
      {head + "endsolid t\ngarbage\n", 10, "garbage", "expected keyword 'solid'"},
  };
  int n = 0;
  for (const Case& c : cases) {
    const std::string p = writeText("m" + std::to_string(n++) + ".stl", c.content);
    const InputError e = expectError(p, "stl:" + p + ":line " + std::to_string(c.line));
    // The file's words are never quoted: only their length.
    EXPECT_EQ(e.value(), c.value == "<end of file>" ? c.value
                                                    : "a word of " + std::to_string(c.value.size()) + " characters");
    EXPECT_NE(std::string(e.what()).find(c.reason), std::string::npos) << e.what();
  }
}

TEST_F(StlFiles, NonFiniteCoordinatesAreRejected) {
  const std::string p =
      writeText("nan.stl", std::string("solid t\n") + kFacet +
                               "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\n");
  const InputError e = expectError(p, "stl:" + p + ":line 12");
  EXPECT_EQ(e.value(), "a word of 3 characters");
  const std::string q = writeText("inf.stl",
                                  "solid t\nfacet normal 0 0 1\nouter loop\n"
                                  "vertex 0 0 0\nvertex 1 0 0\nvertex 0 -inf 0\n");
  expectError(q, "stl:" + q + ":line 6");

  // Binary: overwrite y of vertex 1 of triangle 2 with a float NaN.
  const TriangleMesh box = axisAlignedBoxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  writeStlBinary(path("nan_bin.stl"), box.vertices, box.triangles);
  std::string bytes = readBytes(path("nan_bin.stl"));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(bytes.data() + 84 + 2 * 50 + 12 + 12 * 1 + 4, &nan, 4);  // little-endian host
  writeText("nan_bin.stl", bytes);
  expectError(path("nan_bin.stl"), "stl:" + path("nan_bin.stl") + ":triangle 2");
}

TEST_F(StlFiles, MissingEmptyAndTriangleFreeFilesAreRejected) {
  const std::string missing = path("does_not_exist.stl");
  const InputError e = expectError(missing, "stl:" + missing);
  EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos);
  expectError(dir_.string(), "stl:" + dir_.string());  // a directory
  expectError(writeText("empty.stl", ""), "stl:" + path("empty.stl"));
  expectError(writeText("short.stl", "hello"), "stl:" + path("short.stl"));
  const InputError none =
      expectError(writeText("none.stl", "solid x\nendsolid x\n"), "stl:" + path("none.stl"));
  EXPECT_EQ(none.value(), "0 triangles");
  writeStlBinary(path("none_bin.stl"), {}, {});
  EXPECT_EQ(fs::file_size(path("none_bin.stl")), 84u);
  expectError(path("none_bin.stl"), "stl:" + path("none_bin.stl"));
}

TEST_F(StlFiles, DegenerateTrianglesAreDroppedAndReported) {
  // Bounding box (0,0,0)-(5,5,5): diag^2 = 75, so the area threshold is 7.5e-11.
  const std::vector<Vec3> vs = {Vec3(0, 0, 0),
                                Vec3(1, 0, 0),
                                Vec3(0, 1, 0),
                                Vec3(1, 1, 0),
                                Vec3(0.5, 0, 0),
                                Vec3(5, 5, 5),
                                Vec3(0.5, 0.5 + 1e-12, 0)};
  // 0 good; 1 repeated vertex; 2 good; 3 collinear (area 0); 4 sliver with area
  // 0.5 * |(1,1,0) x (0.5, 0.5 + 1e-12, 0)| = 5e-13 < 7.5e-11; 5 good.
  const Triangles tris = {{0, 1, 2}, {1, 1, 3}, {1, 3, 2}, {0, 4, 1}, {0, 3, 6}, {1, 3, 5}};
  writeStlAscii(path("d.stl"), vs, tris);
  const StlMesh mesh = readStl(path("d.stl"));
  ASSERT_EQ(mesh.triangles.size(), 3u);
  ASSERT_EQ(mesh.warnings.size(), 3u);
  EXPECT_NE(mesh.warnings[0].find("triangle 1 "), std::string::npos) << mesh.warnings[0];
  EXPECT_NE(mesh.warnings[1].find("triangle 3 "), std::string::npos) << mesh.warnings[1];
  EXPECT_NE(mesh.warnings[2].find("triangle 4 "), std::string::npos) << mesh.warnings[2];
  expectSameGeometry(mesh, vs, {tris[0], tris[2], tris[5]});
  // Vertices used only by dropped triangles (0.5,0,0) and the sliver apex are removed.
  EXPECT_EQ(mesh.vertices.size(), 5u);
}

TEST(StlParse, ManyDegenerateTrianglesAreSummarised) {
  std::string text = "solid t\n";
  const auto facet = [&text](const char* a, const char* b, const char* c) {
    text += std::string("facet normal 0 0 0\nouter loop\nvertex ") + a + "\nvertex " + b +
            "\nvertex " + c + "\nendloop\nendfacet\n";
  };
  for (int k = 0; k < 1005; ++k) facet("0 0 0", "1 0 0", "0 0 0");
  facet("0 0 0", "1 0 0", "0 1 0");
  text += "endsolid t\n";
  const StlMesh mesh = parseStl(text, "mem");
  EXPECT_EQ(mesh.triangles.size(), 1u);
  ASSERT_EQ(mesh.warnings.size(), 1001u);
  EXPECT_NE(mesh.warnings[999].find("triangle 999 "), std::string::npos);
  EXPECT_NE(mesh.warnings[1000].find("1005 degenerate"), std::string::npos) << mesh.warnings[1000];
}

TEST_F(StlFiles, AllDegenerateIsAnError) {
  const std::string p =
      writeText("all.stl",
                "solid t\nfacet normal 0 0 0\nouter loop\nvertex 1 1 1\nvertex 1 1 1\n"
                "vertex 1 1 1\nendloop\nendfacet\nendsolid t\n");
  expectError(p, "stl:" + p);
}

TEST_F(StlFiles, LenientAsciiVariantsAreAccepted) {
  // Upper-case keywords, '+' signs, exponents, CRLF, two solids, missing final endsolid.
  const std::string p = writeText(
      "v.stl",
      "SOLID a\r\nFACET NORMAL 0 0 1\r\nOUTER LOOP\r\nVERTEX +0 0 0\r\nVERTEX 1e0 0 0\r\n"
      "VERTEX 0 1.0E+00 0\r\nENDLOOP\r\nENDFACET\r\nENDSOLID a\r\n"
      "solid b\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\n"
      "endloop\nendfacet\n");
  const StlMesh mesh = readStl(p);
  EXPECT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.vertices.size(), 4u);  // (1,0,0) and (0,1,0) shared between the solids
  ASSERT_EQ(mesh.warnings.size(), 1u);
  EXPECT_NE(mesh.warnings[0].find("endsolid"), std::string::npos);
}

/// parseStl must either succeed with a valid mesh or throw InputError; never crash or hang.
void expectGracefulParse(const std::string& data) {
  try {
    const StlMesh mesh = parseStl(data, "fuzz");
    ASSERT_FALSE(mesh.triangles.empty());
    for (const auto& t : mesh.triangles) {
      for (const std::uint32_t i : t) ASSERT_LT(i, mesh.vertices.size());
      ASSERT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
    }
    for (const Vec3& v : mesh.vertices) ASSERT_TRUE(v.allFinite());
  } catch (const InputError&) {
    // expected for most inputs
  }
}

TEST_F(StlFiles, GarbageInputNeverCrashes) {
  std::mt19937_64 rng(31337);
  std::uniform_int_distribution<int> byte(0, 255);
  // Random bytes of many lengths, including the binary size-match case.
  for (std::size_t len : {1u, 5u, 83u, 84u, 85u, 134u, 200u, 1000u}) {
    for (int k = 0; k < 20; ++k) {
      std::string s(len, '\0');
      for (char& ch : s) ch = static_cast<char>(byte(rng));
      if (len == 134) s.replace(80, 4, std::string("\x01\0\0\0", 4));  // count 1 matches size
      expectGracefulParse(s);
    }
  }
  // Every prefix and random mutations of a valid ASCII and a valid binary file.
  const TriangleMesh box = axisAlignedBoxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  writeStlAscii(path("a.stl"), box.vertices, box.triangles);
  writeStlBinary(path("b.stl"), box.vertices, box.triangles);
  for (const std::string& valid : {readBytes(path("a.stl")), readBytes(path("b.stl"))}) {
    for (std::size_t n = 0; n <= valid.size(); n += 3) expectGracefulParse(valid.substr(0, n));
    std::uniform_int_distribution<std::size_t> pos(0, valid.size() - 1);
    for (int k = 0; k < 500; ++k) {
      std::string s = valid;
      for (int m = 0; m < 1 + k % 4; ++m) s[pos(rng)] = static_cast<char>(byte(rng));
      expectGracefulParse(s);
    }
  }
}

TEST_F(StlFiles, WritersValidateInput) {
  EXPECT_THROW(writeStlBinary(path("x.stl"), {Vec3::Zero()}, {{0, 0, 1}}), InputError);
  EXPECT_THROW(writeStlBinary(path("x.stl"), {Vec3(1e300, 0, 0)}, {}), InputError);
  EXPECT_THROW(writeStlAscii(path("x.stl"), {Vec3(NAN, 0, 0)}, {}), InputError);
  EXPECT_THROW(writeStlAscii((dir_ / "no" / "such" / "dir.stl").string(), {}, {}), InputError);
}

}  // namespace
}  // namespace demlink::core
