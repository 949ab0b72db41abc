// Outside text in logs and errors: one line, no control sequences, bounded; and the one
// rule for names.
#include <gtest/gtest.h>

#include <string>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/core/base/names.hpp"

namespace demlink::core {
namespace {

TEST(LogText, EscapesControlBytesAndTruncates) {
  EXPECT_EQ(logText("plain name-1.ok"), "plain name-1.ok");
  EXPECT_EQ(logText("a\nb\r\tc\\d"), "a\\nb\\r\\tc\\\\d");
  EXPECT_EQ(logText("\x1b[31mred\x7f\xc3\xa9"), "\\x1b[31mred\\x7f\\xc3\\xa9");
  const std::string huge(1u << 20, 'x');
  EXPECT_EQ(logText(huge), std::string(kLogTextMaxBytes, 'x') + "...(1048576 bytes)");
  EXPECT_EQ(quotedLogText("q\"", 1), "\"q...(2 bytes)\"");
}

TEST(Names, OneRule) {
  for (const char* good : {"a", "bucket_1", "Pit A (left)", "x.y-z:w+v#u", "..a"}) {
    EXPECT_EQ(nameProblem(good), "") << good;
  }
  EXPECT_NE(nameProblem(""), "");
  EXPECT_NE(nameProblem(std::string(kMaxNameLength + 1, 'n')), "");
  EXPECT_EQ(nameProblem(std::string(kMaxNameLength, 'n')), "");
  for (const std::string bad : {"new\nline", "esc\x1bname", "quote\"", "back\\slash", " lead", "trail ", "\xc3\xa9", "low/drain", ".", ".."}) {
    EXPECT_NE(nameProblem(bad), "") << logText(bad);
    try {
      requireValidName("components[3].name", bad);
      ADD_FAILURE() << "accepted " << logText(bad);
    } catch (const InputError& error) {
      EXPECT_EQ(error.field(), "components[3].name");
      EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace demlink::core
