// Hostile clients on the in-process host: names that would flood or forge the log, file
// paths on the server, durations that overflow the deadline. Each gets a named Error, the
// log stays small and one line per event, and a fresh client is then served as usual.
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <memory>
#include <sstream>

#include "cosim_test_support.hpp"

namespace demlink::server::test {
namespace {

/// Captures what the host logs while alive (the default logger's sinks are swapped).
class LogCapture {
 public:
  LogCapture() : previous_(spdlog::default_logger()) {
    auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(text_);
    sink->set_pattern("[%l] %v");
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("capture", sink));
  }
  ~LogCapture() { spdlog::set_default_logger(previous_); }
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;
  [[nodiscard]] std::string text() const { return text_.str(); }

 private:
  std::shared_ptr<spdlog::logger> previous_;
  std::ostringstream text_;
};

/// A fresh client (connection `id`) declares a box and the small bed, runs 10 steps to
/// the end and gets Finished: the host still serves after whatever came before.
void freshClientRunsToTheEnd(CosimHarness& h, ConnectionId id) {
  h.hello(id, "fresh");
  ASSERT_TRUE(h.errors(id).empty()) << h.errors(id).front().message();
  h.declare(id, boxJson(1e-5, 1e-4, R"("coupling": {"expected_count": 4})", 5e-5));
  for (const std::string& c : smallBedJson()) h.declare(id, c);
  ASSERT_TRUE(h.compiled(id)) << (h.errors(id).empty() ? "" : h.errors(id).front().message());
  runToTheEnd(h, id);
  ASSERT_TRUE(h.finished(id));
  EXPECT_EQ(h.finished(id)->reason(), "end time reached");
}

/// The last Error `id` received.
v1::Error lastError(CosimHarness& h, ConnectionId id) {
  const std::vector<v1::Error> errors = h.errors(id);
  if (errors.empty()) {
    ADD_FAILURE() << "no Error for connection " << id;
    return {};
  }
  return errors.back();
}

TEST(CosimLimits, ClientNamesAreCheckedAndLoggedEscaped) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  LogCapture log;
  h.hello(1, std::string(64u << 20, 'x'));  // 64 MiB: once logged whole, 201 MB of log
  EXPECT_EQ(lastError(h, 1).code(), v1::Error::INVALID_INPUT);
  EXPECT_EQ(lastError(h, 1).field(), "hello.client_name");
  EXPECT_TRUE(h.closed(1));
  EXPECT_LT(lastError(h, 1).message().size(), 400u);
  h.hello(2, "bob\n[12:00:00] error: the server was hacked");
  EXPECT_EQ(lastError(h, 2).field(), "hello.client_name");
  EXPECT_TRUE(h.closed(2));

  // A Bye reason (free text) is logged escaped and truncated.
  h.hello(3, "carol");
  v1::ClientMessage bye;
  bye.mutable_bye()->set_reason("done\n[12:00:00] error: forged\x1b[31m" + std::string(1u << 20, 'r'));
  h.take(h.host().received(3, bye, h.now()));
  const std::string text = log.text();
  EXPECT_LT(text.size(), 8192u) << "log of " << text.size() << " bytes";
  EXPECT_EQ(text.find("\n[12:00:00] error"), std::string::npos) << text;
  EXPECT_EQ(text.find('\x1b'), std::string::npos);
  EXPECT_NE(text.find("done\\n[12:00:00] error: forged\\x1b[31m"), std::string::npos) << text;
  freshClientRunsToTheEnd(h, 4);
}

TEST(CosimLimits, ComponentNamesAreCheckedAtDeclare) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  LogCapture log;
  h.hello(1, "alice");
  h.declare(1, R"({"name": ")" + std::string(10u << 20, 'c') + R"(", "material": {}})");
  EXPECT_EQ(lastError(h, 1).code(), v1::Error::INVALID_DECLARATION);
  EXPECT_EQ(lastError(h, 1).field(), "component.name");
  EXPECT_LT(lastError(h, 1).message().size(), 400u);
  h.declare(1, R"({"name": "two\nlines", "material": {}})");
  EXPECT_EQ(lastError(h, 1).field(), "component.name");
  EXPECT_LT(log.text().size(), 4096u);
  EXPECT_EQ(log.text().find("two\nlines"), std::string::npos);
  h.bye(1);
  freshClientRunsToTheEnd(h, 2);
}

/// A list from a client (100,000 expected names) and a 60,000-byte Hello.simulation: the
/// Errors name the first few and the count, the log stays small, and a name that would be
/// a path ('/', "..") is refused at Declare.
TEST(CosimLimits, ListsAndLongTextFromClientsAreCutInErrorsAndLogs) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  LogCapture log;
  h.hello(1, "alice", "group");
  v1::ComponentDeclaration box = declarationOf(boxJson(1e-5, 0.0, "", 1e-4));
  for (int k = 0; k < 100000; ++k) box.mutable_simulation_box()->mutable_coupling()->add_expected_names("part-" + std::to_string(k));
  v1::ClientMessage declare;
  *declare.mutable_declare()->mutable_component() = box;
  h.take(h.host().received(1, declare, h.now()));
  ASSERT_TRUE(h.errors(1).empty()) << h.errors(1).front().message();
  h.hello(2, "bob", std::string(60000, 'g'));
  const v1::Error other = lastError(h, 2);
  EXPECT_EQ(other.code(), v1::Error::OUT_OF_ORDER);
  EXPECT_LT(other.message().size(), 1000u) << other.message().size();
  EXPECT_NE(other.message().find("held by client \"alice\" (connection 1)"), std::string::npos) << other.message();
  EXPECT_NE(other.message().find("assembly times out in"), std::string::npos) << other.message();
  h.take(h.host().expireAssemblyNow(h.now()));
  const v1::Error timeout = lastError(h, 1);
  EXPECT_EQ(timeout.code(), v1::Error::TIMEOUT);
  EXPECT_LT(timeout.message().size(), 1000u) << timeout.message().size();
  EXPECT_NE(timeout.message().find("\"part-4\" and 99995 more (100000 in all)"), std::string::npos)
      << timeout.message();
  EXPECT_LT(log.text().size(), 8192u) << "the log holds every name";

  for (const char* name : {"a/b", "..", "."}) {
    h.hello(3, "carol");
    h.declare(3, std::string(R"({"name": ")") + name + R"(", "material": {}})");
    EXPECT_EQ(lastError(h, 3).code(), v1::Error::INVALID_DECLARATION) << name;
    EXPECT_EQ(lastError(h, 3).field(), "component.name") << name;
    h.bye(3);
  }
}

TEST(CosimLimits, ClientFilePathsNeedADataRoot) {
  ScratchDir dir;
  const std::string body = R"({"name": "bucket", "communication_interval": 5e-5, "rigid_body": {"material": "glass",
      "stl_file": ")";
  {
    CosimHarness h(dir.path() / "none");
    h.hello(1, "alice");
    h.declare(1, boxJson(1e-5, 1e-4, R"("coupling": {"expected_count": 3})", 5e-5));
    h.declare(1, smallBedJson()[0]);
    h.declare(1, body + R"(/etc/passwd"}})");
    EXPECT_EQ(lastError(h, 1).code(), v1::Error::INVALID_DECLARATION);
    EXPECT_EQ(lastError(h, 1).field(), "bucket.rigid_body.stl_file");
    EXPECT_NE(lastError(h, 1).message().find("without --data-root"), std::string::npos) << lastError(h, 1).message();
    EXPECT_EQ(lastError(h, 1).message().find("root:"), std::string::npos);
    freshClientRunsToTheEnd(h, 2);
  }
  // With a data root: paths below it (relative to it) only, symlinks resolved; a device
  // is not a regular file.
  std::filesystem::create_directories(dir.path() / "data");
  writeText(dir.path() / "data" / "cube.stl", "solid c\nendsolid c\n");
  std::filesystem::create_symlink("/etc/passwd", dir.path() / "data" / "link.stl");
  CosimOptions options = CosimHarness::options(dir.path() / "rooted", {}, {});
  options.data_root = dir.path() / "data";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"../../../etc/passwd", "lies outside the server's data root"},
      {"link.stl", "lies outside the server's data root"},
      {"/dev/zero", "lies outside the server's data root"},
      {"missing.stl", "file not found"},
      {"cube.stl", "contains no triangles"},  // inside: read, and its own error names the file
  };
  for (const auto& [path, reason] : cases) {
    CosimHost host(options);
    v1::Hello hello;
    hello.set_protocol_version(1);
    hello.set_client_name("alice");
    (void)host.connected(1, hello, SteadyClock::time_point{});
    std::vector<Outgoing> out;
    for (const std::string& json : {boxJson(1e-5, 1e-4, R"("coupling": {"expected_count": 3})", 5e-5),
                                    smallBedJson()[0], body + path + "\"}}"}) {
      v1::ClientMessage m;
      *m.mutable_declare()->mutable_component() = declarationOf(json);
      for (Outgoing& o : host.received(1, m, SteadyClock::time_point{})) out.push_back(std::move(o));
    }
    const auto refused = std::find_if(out.begin(), out.end(), [](const Outgoing& o) { return o.message.has_error(); });
    ASSERT_NE(refused, out.end()) << path;
    const v1::Error& error = refused->message.error();
    EXPECT_EQ(error.field(), "bucket.rigid_body.stl_file") << error.message();
    EXPECT_NE(error.message().find(reason), std::string::npos) << path << ": " << error.message();
    EXPECT_EQ(error.message().find("root:"), std::string::npos) << error.message();
  }
}

TEST(CosimLimits, DurationsAreValidatedAndDeadlinesNeverOverflow) {
  ScratchDir dir;
  CosimHarness h(dir.path());
  h.hello(1, "alice");
  h.declare(1, boxJson(1e-5, 1e-4, R"("coupling": {"expected_count": 1, "client_timeout": 1e308})", 5e-5));
  EXPECT_EQ(lastError(h, 1).code(), v1::Error::INVALID_DECLARATION);
  EXPECT_EQ(lastError(h, 1).field(), "box.simulation_box.coupling.client_timeout");
  freshClientRunsToTheEnd(h, 2);

  // The server's own timeout far beyond the bound: clamped to kMaxWaitSeconds, so the
  // deadline lies in the future instead of wrapping around to "now".
  CosimOptions options = CosimHarness::options(dir.path() / "long", {}, {});
  options.client_timeout_s = 1e308;
  CosimHost host(options);
  v1::Hello hello;
  hello.set_protocol_version(1);
  const SteadyClock::time_point start{};
  (void)host.connected(1, hello, start);
  for (const std::string& json :
       {boxJson(1e-5, 1e-4, R"("coupling": {"expected_count": 2})", 5e-5), smallBedJson()[0]}) {
    v1::ClientMessage m;
    *m.mutable_declare()->mutable_component() = declarationOf(json);
    (void)host.received(1, m, start);
  }
  ASSERT_TRUE(host.simulationRunning());
  const std::optional<SteadyClock::time_point> deadline = host.nextDeadline();
  ASSERT_TRUE(deadline);
  EXPECT_GT(*deadline, start + std::chrono::hours(24 * 6));
  EXPECT_TRUE(host.poll(start + std::chrono::hours(1)).empty()) << "no timeout after an hour";
}

}  // namespace
}  // namespace demlink::server::test
