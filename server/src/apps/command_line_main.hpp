#pragma once
/// The exit-code convention shared by the command-line tools (demlink-run, demlink-server):
/// bad input (core::InputError, which names the field and value) exits 2, a run the
/// watchdog stopped (core::SimulationFault, naming the check) 3, any other failure 1, each
/// with one "error: ..." line on stderr; nothing escapes main() as a crash.
#include <cstdio>
#include <exception>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/step/watchdog.hpp"

namespace demlink::server {

/// Calls run(argc, argv) and turns exceptions into the exit codes above.
inline int runCommandLine(int (*run)(int, char**), int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const core::InputError& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 2;
  } catch (const core::SimulationFault& fault) {
    std::fprintf(stderr, "error: %s\n", fault.what());
    return 3;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 1;
  } catch (...) {
    std::fputs("error: unknown failure\n", stderr);
    return 1;
  }
}

}  // namespace demlink::server
