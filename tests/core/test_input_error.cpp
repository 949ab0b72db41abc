// InputError keeps field, value and reason apart: what() is formatted once, a translator
// puts the scene path in front with within(), and a file's error renamed to the field that
// named the file keeps its place inside the file without repeating "<field> = <value>".
#include <gtest/gtest.h>

#include <string>

#include "demlink/core/base/input_error.hpp"

namespace demlink::core {
namespace {

std::size_t countOf(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++n;
  return n;
}

TEST(InputError, KeepsFieldValueAndReasonApart) {
  const InputError e("time_step", "0.1", "exceeds the critical limit");
  EXPECT_EQ(e.field(), "time_step");
  EXPECT_EQ(e.value(), "0.1");
  EXPECT_EQ(e.reason(), "exceeds the critical limit");
  EXPECT_STREQ(e.what(), "time_step = 0.1: exceeds the critical limit");
}

TEST(InputError, WithinPutsTheScenePathInFront) {
  const InputError e("time_step", "0.1", "too large");
  EXPECT_EQ(e.within("simulation_box").field(), "simulation_box.time_step");
  EXPECT_STREQ(e.within("box.simulation_box").what(), "box.simulation_box.time_step = 0.1: too large");
  EXPECT_EQ(InputError("[2].name", "x", "r").within("materials").field(), "materials[2].name");
  EXPECT_EQ(InputError("", "x", "r").within("materials[0]").field(), "materials[0]");
  EXPECT_EQ(e.within("").field(), "time_step");
  EXPECT_EQ(e.within("simulation_box").reason(), "too large");
}

TEST(InputError, AsNamesTheFieldOnceAndKeepsThePlaceInTheFile) {
  const InputError inFile("/data/part.stl:12", "vertex 3", "not a number");
  const InputError renamed = inFile.as("bucket.stl_file");
  EXPECT_EQ(renamed.field(), "bucket.stl_file");
  EXPECT_EQ(renamed.value(), "vertex 3");
  EXPECT_EQ(renamed.reason(), "/data/part.stl:12: not a number");
  EXPECT_EQ(countOf(renamed.what(), " = "), 1u) << renamed.what();
  EXPECT_EQ(InputError("bucket.stl_file", "x", "r").as("bucket.stl_file").reason(), "r");
}

}  // namespace
}  // namespace demlink::core
