// The view's HTTP request parser: complete and split requests, queries, and every refusal.
#include <gtest/gtest.h>

#include <string>

#include "demlink/server/view/http_request.hpp"

namespace demlink::server {
namespace {

using State = HttpRequestParser::State;

const std::string kRequest =
    "GET /ws?token=a%20b+c&rate=10 HTTP/1.1\r\nHost: 127.0.0.1:8080\r\nUpgrade: websocket\r\n"
    "Connection: keep-alive, Upgrade\r\nX-Twice: one\r\nx-twice: two\r\n\r\nleft";

TEST(HttpRequest, ParsesLinePathQueryAndHeaders) {
  HttpRequestParser parser;
  ASSERT_EQ(parser.feed(kRequest), State::kComplete) << parser.errorReason();
  const HttpRequest& request = parser.request();
  EXPECT_EQ(request.method, "GET");
  EXPECT_EQ(request.path, "/ws");
  EXPECT_EQ(request.query.at("token"), "a b c");
  EXPECT_EQ(request.query.at("rate"), "10");
  EXPECT_EQ(request.header("host").value_or(""), "127.0.0.1:8080");
  EXPECT_EQ(request.header("x-twice").value_or(""), "one, two");
  EXPECT_TRUE(request.headerListsToken("connection", "upgrade"));
  EXPECT_FALSE(request.headerListsToken("connection", "close"));
  EXPECT_EQ(parser.leftover(), "left");
}

TEST(HttpRequest, SameResultWhateverTheSplit) {
  for (std::size_t chunk : {1u, 2u, 7u, 64u}) {
    HttpRequestParser parser;
    State state = State::kIncomplete;
    for (std::size_t at = 0; at < kRequest.size(); at += chunk) {
      state = parser.feed(std::string_view(kRequest).substr(at, chunk));
      if (state != State::kIncomplete) break;
    }
    ASSERT_EQ(state, State::kComplete) << "chunk " << chunk;
    EXPECT_EQ(parser.request().query.at("token"), "a b c");
  }
}

TEST(HttpRequest, IncompleteUntilTheBlankLine) {
  HttpRequestParser parser;
  EXPECT_EQ(parser.feed("GET / HTTP/1.1\r\nHost: x\r\n"), State::kIncomplete);
  EXPECT_EQ(parser.feed("\r\n"), State::kComplete);
  EXPECT_EQ(parser.request().path, "/");
}

struct Refusal {
  std::string request;
  int status;
};

TEST(HttpRequest, RefusesWithTheRightStatus) {
  const Refusal cases[] = {
      {"POST / HTTP/1.1\r\n\r\n", 405},
      {"GET / HTTP/2.0\r\n\r\n", 505},
      {"GET index.html HTTP/1.1\r\n\r\n", 400},
      {"GET /%zz HTTP/1.1\r\n\r\n", 400},
      {"GET /a%00b HTTP/1.1\r\n\r\n", 400},
      {"GET / HTTP/1.1\r\nNo colon here\r\n\r\n", 400},
      {"GET / HTTP/1.1\r\nBad Name: x\r\n\r\n", 400},
      {"GET / HTTP/1.1\r\nContent-Length: 5\r\n\r\nhello", 400},
      {"GET /" + std::string(3000, 'a') + " HTTP/1.1\r\n\r\n", 414},
      {"GARBAGE\r\n\r\n", 400},
  };
  for (const Refusal& refusal : cases) {
    HttpRequestParser parser;
    EXPECT_EQ(parser.feed(refusal.request), State::kError) << refusal.request.substr(0, 40);
    EXPECT_EQ(parser.errorStatus(), refusal.status) << refusal.request.substr(0, 40);
    EXPECT_FALSE(parser.errorReason().empty());
  }
}

TEST(HttpRequest, BoundsTheHeaderBlock) {
  HttpRequestParser parser;
  std::string endless = "GET / HTTP/1.1\r\n";
  State state = parser.feed(endless);
  // A client that never ends its header block is refused once it passes the limit.
  for (int k = 0; k < 1000 && state == State::kIncomplete; ++k) state = parser.feed("X-Fill: 0123456789\r\n");
  EXPECT_EQ(state, State::kError);
  EXPECT_EQ(parser.errorStatus(), 431);

  std::string many = "GET / HTTP/1.1\r\n";
  for (int k = 0; k < 65; ++k) many += "X-" + std::to_string(k) + ": v\r\n";
  HttpRequestParser fields;
  EXPECT_EQ(fields.feed(many + "\r\n"), State::kError);
  EXPECT_EQ(fields.errorStatus(), 431);
}

TEST(HttpRequest, PercentDecoding) {
  EXPECT_EQ(percentDecode("a%2Fb+c", false).value_or("?"), "a/b+c");
  EXPECT_EQ(percentDecode("a%2fb+c", true).value_or("?"), "a/b c");
  EXPECT_FALSE(percentDecode("%4", false).has_value());
  EXPECT_FALSE(percentDecode("%g0", false).has_value());
}

}  // namespace
}  // namespace demlink::server
