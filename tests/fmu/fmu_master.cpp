/// A small FMI 2.0 Co-Simulation master for the DEMLink FMU test: unpacks the .fmu, reads
/// modelDescription.xml for the model identifier, GUID and value references, loads the
/// library of its platform (linux64, or win64 in the win64 build) and runs the
/// plate-into-bed scenario of plate_in_bed.cfg against a server.
/// Usage: fmu_master FMU HOST PORT WORKDIR [end | coupled MASS DURATION]. Prints one
/// summary line; exit 0 when every physical and timing check holds, 1 otherwise (the reason
/// on stderr). With "end" it steps short_run.cfg until the server ends the run and checks
/// fmi2Discard and fmi2Terminated. With "coupled" it drops a plate of MASS kg onto the bed
/// for DURATION s, integrating its fall from the force each step returns
/// (tests/coupling/coupled_plate.hpp), and prints that summary instead. Timing: after fmi2DoStep(t, h) the box's time must be t + h in the
/// send-first order (FMI 2.0: outputs at the step's end) and t in the receive-first one
/// (the interval [t - h, t], one interval behind).
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>

#include "../coupling/coupled_plate.hpp"
#include "fmi2.h"
#include "fmu_config.hpp"
#include "shared_library.hpp"
#include "zip_writer.hpp"

namespace {

void logger(fmi2ComponentEnvironment, fmi2String instance, fmi2Status status, fmi2String category, fmi2String message,
            ...) {
  va_list args;
  va_start(args, message);
  std::fprintf(stderr, "[%s %d %s] ", instance, static_cast<int>(status), category);
  std::vfprintf(stderr, message, args);
  std::fprintf(stderr, "\n");
  va_end(args);
}

int failWith(const std::string& why) {
  std::fprintf(stderr, "fmu_master: %s\n", why.c_str());
  return 1;
}

template <class F>
F symbol(const demlink::fmu::SharedLibrary& library, const char* name) {
  const F s = library.function<F>(name);
  if (s == nullptr) {
    std::fprintf(stderr, "fmu_master: %s is not exported\n", name);
    std::exit(1);
  }
  return reinterpret_cast<F>(s);
}

}  // namespace

int main(int argc, char** argv) {
  const bool coupled = argc == 8 && std::string(argv[5]) == "coupled";
  if (argc != 5 && !(argc == 6 && std::string(argv[5]) == "end") && !coupled) {
    std::fprintf(stderr, "usage: %s FMU HOST PORT WORKDIR [end | coupled MASS DURATION]\n", argv[0]);
    return 2;
  }
  const std::filesystem::path work = argv[4];
  std::string xml;
  try {
    for (const demlink::fmu::ZipEntry& e : demlink::fmu::readStoredZip(demlink::fmu::readFile(argv[1]))) {
      const std::filesystem::path file = work / e.name;
      std::filesystem::create_directories(file.parent_path());
      std::ofstream(file, std::ios::binary) << e.data;
    }
    xml = demlink::fmu::readFile((work / "modelDescription.xml").string());
  } catch (const std::exception& e) {
    return failWith(e.what());
  }
  std::smatch m;
  if (!std::regex_search(xml, m, std::regex("modelIdentifier=\"([A-Za-z0-9_]+)\""))) return failWith("no modelIdentifier");
  const std::string model = m[1];
  if (!std::regex_search(xml, m, std::regex("guid=\"([^\"]+)\""))) return failWith("no guid");
  const std::string guid = m[1];
  std::map<std::string, fmi2ValueReference> vr;
  const std::regex variable("name=\"([^\"]+)\" valueReference=\"([0-9]+)\"");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), variable); it != std::sregex_iterator(); ++it) {
    vr[(*it)[1]] = static_cast<fmi2ValueReference>(std::stoul((*it)[2]));
  }
  auto ref = [&](const std::string& name) {
    if (!vr.contains(name)) {
      std::fprintf(stderr, "fmu_master: no variable %s\n", name.c_str());
      std::exit(1);
    }
    return vr[name];
  };

  const demlink::fmu::SharedLibrary library(
      (work / "binaries" / demlink::fmu::kFmiPlatform / (model + demlink::fmu::kLibrarySuffix)).string());
  if (!library.loaded()) return failWith(library.error());
  const auto instantiate = symbol<decltype(&fmi2Instantiate)>(library, "fmi2Instantiate");
  const auto setupExperiment = symbol<decltype(&fmi2SetupExperiment)>(library, "fmi2SetupExperiment");
  const auto enterInit = symbol<decltype(&fmi2EnterInitializationMode)>(library, "fmi2EnterInitializationMode");
  const auto exitInit = symbol<decltype(&fmi2ExitInitializationMode)>(library, "fmi2ExitInitializationMode");
  const auto setReal = symbol<decltype(&fmi2SetReal)>(library, "fmi2SetReal");
  const auto getReal = symbol<decltype(&fmi2GetReal)>(library, "fmi2GetReal");
  const auto setInteger = symbol<decltype(&fmi2SetInteger)>(library, "fmi2SetInteger");
  const auto getInteger = symbol<decltype(&fmi2GetInteger)>(library, "fmi2GetInteger");
  const auto setString = symbol<decltype(&fmi2SetString)>(library, "fmi2SetString");
  const auto doStep = symbol<decltype(&fmi2DoStep)>(library, "fmi2DoStep");
  const auto terminate = symbol<decltype(&fmi2Terminate)>(library, "fmi2Terminate");
  const auto freeInstance = symbol<decltype(&fmi2FreeInstance)>(library, "fmi2FreeInstance");
  if (std::string(symbol<decltype(&fmi2GetVersion)>(library, "fmi2GetVersion")()) != "2.0") return failWith("version");

  demlink::fmu::FmuConfig config;
  try {
    config = demlink::fmu::readConfigFile((work / "resources" / "demlink_fmu.cfg").string());
  } catch (const std::exception& e) {
    return failWith(e.what());
  }
  const bool sendFirst = config.exchange_order == demlink::fmu::ExchangeOrder::kSendFirst;
  // The DEM time the outputs after fmi2DoStep(t, h) must describe (the end of their interval).
  const auto expectedOutputTime = [&](double t, double h) { return sendFirst ? t + h : t; };
  double maxTimeError = 0.0;
  const fmi2CallbackFunctions callbacks{logger, nullptr, nullptr, nullptr, nullptr};
  // file:///dir, or file:///C:/dir on Windows.
  std::string resourcePath = std::filesystem::absolute(work / "resources").generic_string();
  if (!resourcePath.starts_with("/")) resourcePath.insert(0, "/");
  const std::string resources = "file://" + resourcePath;
  if (coupled) {
    fmi2Component fmu = instantiate("coupled", fmi2CoSimulation, guid.c_str(), resources.c_str(), &callbacks,
                                    fmi2False, fmi2False);
    const fmi2ValueReference settings[2] = {ref("port"), ref("timeout")};
    const fmi2Integer port = std::atoi(argv[3]);
    const fmi2Real timeout = 300.0;  // the bed settles before Compiled [s]
    const fmi2ValueReference hostRef = ref("host");
    const fmi2String host = argv[2];
    if (fmu == nullptr || setString(fmu, &hostRef, 1, &host) != fmi2OK || setInteger(fmu, &settings[0], 1, &port) != fmi2OK ||
        setReal(fmu, &settings[1], 1, &timeout) != fmi2OK || enterInit(fmu) != fmi2OK || exitInit(fmu) != fmi2OK) {
      return failWith("initialization failed");
    }
    const fmi2ValueReference z = ref("plate.position[3]");
    const fmi2ValueReference vz = ref("plate.velocity[3]");
    const fmi2ValueReference force = ref("plate.meanForce[3]");
    const double h = config.interval_s;
    const double duration = std::atof(argv[7]);
    demlink::coupling::CoupledPlate dynamics(std::atof(argv[6]));
    for (int k = 0; k * h < duration - 0.5 * h; ++k) {
      const fmi2Real state[2] = {dynamics.height(), dynamics.velocity()};
      fmi2Real fz = 0.0;
      if (setReal(fmu, &z, 1, &state[0]) != fmi2OK || setReal(fmu, &vz, 1, &state[1]) != fmi2OK ||
          doStep(fmu, k * h, h, fmi2True) != fmi2OK || getReal(fmu, &force, 1, &fz) != fmi2OK) {
        return failWith("step " + std::to_string(k) + " failed");
      }
      dynamics.advance(fz, h);
    }
    dynamics.printSummary(sendFirst ? "fmu" : "fmu_receive_first", h, std::nan(""));
    const bool ok = terminate(fmu) == fmi2OK;
    freeInstance(fmu);
    return ok ? 0 : failWith("fmi2Terminate failed");
  }
  if (argc == 6) {
    // The box's end time is 10 ms: the steps whose answers end by then succeed (send first:
    // 0..4, ending at 2..10 ms; receive first: 0..5, ending at 0..10 ms), the next one finds
    // the run finished.
    const auto getBooleanStatus = symbol<decltype(&fmi2GetBooleanStatus)>(library, "fmi2GetBooleanStatus");
    fmi2Component fmu = instantiate("short", fmi2CoSimulation, guid.c_str(), resources.c_str(), &callbacks,
                                    fmi2False, fmi2False);
    const fmi2ValueReference portRef = ref("port");
    const fmi2Integer port = std::atoi(argv[3]);
    if (fmu == nullptr || setInteger(fmu, &portRef, 1, &port) != fmi2OK || enterInit(fmu) != fmi2OK ||
        exitInit(fmu) != fmi2OK) {
      return failWith("initialization failed");
    }
    int k = 0;
    fmi2Status status = fmi2OK;
    const fmi2ValueReference timeRef = ref("box.time");
    while (k < 100 && (status = doStep(fmu, k * 0.002, 0.002, fmi2True)) == fmi2OK) {
      fmi2Real demTime = 0.0;
      if (getReal(fmu, &timeRef, 1, &demTime) != fmi2OK) return failWith("fmi2GetReal failed");
      maxTimeError = std::max(maxTimeError, std::fabs(demTime - expectedOutputTime(k * 0.002, 0.002)));
      ++k;
    }
    fmi2Boolean terminated = fmi2False;
    getBooleanStatus(fmu, fmi2Terminated, &terminated);
    std::printf("fmu_master: end after %d steps, status %d, terminated %d, %s, output time error %g s\n", k,
                static_cast<int>(status), static_cast<int>(terminated), sendFirst ? "send_first" : "receive_first",
                maxTimeError);
    std::fflush(stdout);
    const bool ok = status == fmi2Discard && terminated == fmi2True && terminate(fmu) == fmi2OK;
    freeInstance(fmu);
    if (maxTimeError > 1e-9) return failWith("box.time is not the end of the interval the step's order reports");
    return ok ? 0 : failWith("the server's end of the run is not fmi2Discard with fmi2Terminated");
  }
  // Refusals (logged, no server involved): another GUID, Model Exchange, a step before
  // initialization, setting an output.
  if (instantiate("wrongGuid", fmi2CoSimulation, "{00000000-0000-0000-0000-000000000000}", resources.c_str(),
                  &callbacks, fmi2False, fmi2False) != nullptr ||
      instantiate("modelExchange", fmi2ModelExchange, guid.c_str(), resources.c_str(), &callbacks, fmi2False,
                  fmi2False) != nullptr) {
    return failWith("an FMU with another GUID or as Model Exchange was instantiated");
  }
  {
    fmi2Component early = instantiate("early", fmi2CoSimulation, guid.c_str(), resources.c_str(), &callbacks,
                                      fmi2False, fmi2False);
    const fmi2ValueReference output = ref("plate.meanForce[3]");
    const fmi2Real value = 1.0;
    if (early == nullptr || doStep(early, 0.0, 0.002, fmi2True) != fmi2Error ||
        setReal(early, &output, 1, &value) != fmi2Error) {
      return failWith("a step before initialization or setting an output was accepted");
    }
    freeInstance(early);
  }
  fmi2Component fmu = instantiate("plate", fmi2CoSimulation, guid.c_str(), resources.c_str(), &callbacks, fmi2False,
                                  fmi2False);
  if (fmu == nullptr) return failWith("fmi2Instantiate returned NULL");
  const fmi2ValueReference hostRef = ref("host");
  const fmi2ValueReference portRef = ref("port");
  const fmi2String host = argv[2];
  const fmi2Integer port = std::atoi(argv[3]);
  const double h = 0.002;
  const double speed = 0.25;      // plate lowered at 0.25 m/s [m/s]
  const double startZ = 0.11;     // plate centre at the start [m]
  const double finalZ = 0.05;     // plate bottom 45 mm above the floor, 15-35 mm into the bed [m]
  const double bedTop = 0.08;     // the pit's target height: the bed's top is at most this [m]
  const int steps = static_cast<int>(std::lround((startZ - finalZ) / speed / h));
  fmi2ValueReference poseRefs[13];
  const char* const inputs[13] = {"position[1]", "position[2]", "position[3]", "orientation[1]", "orientation[2]",
                                  "orientation[3]", "orientation[4]", "velocity[1]", "velocity[2]", "velocity[3]",
                                  "angularVelocity[1]", "angularVelocity[2]", "angularVelocity[3]"};
  for (int i = 0; i < 13; ++i) poseRefs[i] = ref(std::string("plate.") + inputs[i]);
  const fmi2ValueReference outRefs[6] = {ref("plate.meanForce[1]"), ref("plate.meanForce[2]"),
                                         ref("plate.meanForce[3]"), ref("plate.bodyPosition[3]"),
                                         ref("box.totalMass"), ref("box.time")};
  const fmi2ValueReference countRef = ref("box.particleCount");

  const fmi2ValueReference timeoutRef = ref("timeout");
  const fmi2Real timeout = 300.0;  // the bed settles before Compiled: slow on a loaded machine [s]
  if (setString(fmu, &hostRef, 1, &host) != fmi2OK || setInteger(fmu, &portRef, 1, &port) != fmi2OK ||
      setReal(fmu, &timeoutRef, 1, &timeout) != fmi2OK ||
      setupExperiment(fmu, fmi2False, 0.0, 0.0, fmi2False, 0.0) != fmi2OK || enterInit(fmu) != fmi2OK) {
    return failWith("setting up the instance failed");
  }
  double pose[13] = {0, 0, startZ, 1, 0, 0, 0, 0, 0, -speed, 0, 0, 0};
  if (setReal(fmu, poseRefs, 13, pose) != fmi2OK || exitInit(fmu) != fmi2OK) return failWith("initialization failed");

  // The bed's top is at most the target height and within one diameter (20 mm) below it
  // (docs/sources.md): the plate's bottom (5 mm below its centre) is clear of it above
  // the target height.
  const double clearZ = bedTop;
  double out[6] = {};
  double initialMass = 0.0;
  double previousZ = startZ;
  double maxClearForce = 0.0;
  double maxLagError = 0.0;
  double halfwayForceZ = 0.0;  // mean vertical force when the plate is halfway down [N]
  bool halfway = false;
  for (int k = 0; k <= steps; ++k) {
    const double t = k * h;
    pose[2] = startZ - speed * t;
    if (setReal(fmu, poseRefs, 13, pose) != fmi2OK) return failWith("fmi2SetReal failed");
    if (doStep(fmu, t, h, fmi2True) != fmi2OK) return failWith("fmi2DoStep failed at t = " + std::to_string(t));
    if (getReal(fmu, outRefs, 6, out) != fmi2OK) return failWith("fmi2GetReal failed");
    // The body moves (PREDICTED) over each interval from the pose sent at its start with the
    // sent velocity. Send first: the step from t reports [t, t + h], so the body ends at the
    // pose sent now moved by one interval. Receive first: it reports [t - h, t], which began
    // at the pose sent one step before.
    const double expectedZ = sendFirst ? pose[2] - speed * h : (k == 0 ? startZ : previousZ - speed * h);
    maxLagError = std::max(maxLagError, std::fabs(out[3] - expectedZ));
    maxTimeError = std::max(maxTimeError, std::fabs(out[5] - expectedOutputTime(t, h)));
    if (k == 0) initialMass = out[4];
    if (out[3] - 0.005 > clearZ) maxClearForce = std::max(maxClearForce, std::fabs(out[2]));
    if (!halfway && out[3] <= 0.5 * (clearZ + 0.005 + finalZ)) {
      halfway = true;
      halfwayForceZ = out[2];
    }
    previousZ = pose[2];
  }
  fmi2Integer particles = 0;
  getInteger(fmu, &countRef, 1, &particles);
  const double finalForceZ = out[2];
  const double depth = bedTop - 0.02 - (out[3] - 0.005);  // at least this deep [m]
  // Lower bound: the plate carries at least the weight of the bulk column it displaced
  // (bulk density = solid density 2650 kg/m^3 x solid fraction >= 0.35, docs/sources.md).
  const double columnWeight = 2650.0 * 0.35 * 9.81 * 0.06 * 0.06 * std::max(depth, 0.0);
  std::printf("fmu_master: %d steps, t = %g s, particles %d, mass %g kg, plate z %g m, mean force (%g, %g, %g) N, "
              "clear force %g N, halfway force %g N, body position error %g m, output time error %g s, column weight %g N\n",
              steps + 1, out[5], particles, out[4], out[3], out[0], out[1], out[2], maxClearForce, halfwayForceZ, maxLagError,
              maxTimeError, columnWeight);
  std::fflush(stdout);
  int status = 0;
  if (terminate(fmu) != fmi2OK) status = failWith("fmi2Terminate failed");
  freeInstance(fmu);
  if (maxLagError > 1e-9) status = failWith("body position is not the end of the interval the step reports");
  if (maxTimeError > 1e-9) status = failWith("box.time is not the end of the interval the step reports");
  if (maxClearForce != 0.0) status = failWith("force on the plate while it is clear of the bed");
  if (!(finalForceZ > columnWeight && columnWeight > 0.0)) status = failWith("no upward force in the bed");
  if (!(halfway && finalForceZ > halfwayForceZ)) status = failWith("the bed's resistance does not grow with depth");
  if (!(std::fabs(out[0]) < 0.5 * finalForceZ && std::fabs(out[1]) < 0.5 * finalForceZ)) {
    status = failWith("horizontal force not small against the vertical one (symmetric plate)");
  }
  if (particles < 100 || std::fabs(out[4] - initialMass) > 1e-9 * initialMass) {
    status = failWith("the bed's particles or mass changed");
  }
  return status;
}
