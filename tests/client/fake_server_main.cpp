/// The scripted fake server as a program, so that tests of the C ABI (whose shared library
/// carries its own copy of the protobuf messages) and the Modelica call-sequence program
/// run against it in another process.
///
/// Usage: demlink_fake_server --connections N --components M [--time-step S] [--log FILE]
/// Prints "PORT <port>" on stdout once listening. Exit status 0 when every check of the
/// script passed; otherwise 1 and the reason on stderr. The log file lists "step:name" for
/// every package received, then "DECL <name> <declaration>" for every declaration.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include "fake_server.hpp"

int main(int argc, char** argv) {
  demlink::testing::MiniScheduler scheduler;
  std::string logPath;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    const char* value = argv[i + 1];
    if (flag == "--connections") scheduler.connections = std::atoi(value);
    else if (flag == "--components") scheduler.expectedComponents = static_cast<std::size_t>(std::atoi(value));
    else if (flag == "--time-step") scheduler.time_step = std::atof(value);
    else if (flag == "--log") logPath = value;
    else {
      std::cerr << "unknown flag " << flag << '\n';
      return 2;
    }
  }
  std::vector<std::string> log;
  std::vector<demlink::v1::ComponentDeclaration> declarations;
  scheduler.log = &log;
  scheduler.declarations = &declarations;

  demlink::testing::FakeServer server;
  std::cout << "PORT " << server.port() << std::endl;
  server.start(scheduler);
  const std::string failure = server.finish();
  if (!logPath.empty()) {
    std::ofstream out(logPath);
    for (const auto& line : log) out << line << '\n';
    for (const auto& d : declarations) out << "DECL " << d.name() << ' ' << d.ShortDebugString() << '\n';
  }
  if (!failure.empty()) {
    std::cerr << "fake server: " << failure << '\n';
    return 1;
  }
  return 0;
}
