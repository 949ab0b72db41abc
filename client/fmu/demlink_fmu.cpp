/// The DEMLink FMU: an FMI 2.0 Co-Simulation slave on the C ABI (docs/fmi.md).
///
/// One instance is one DEMLink client (one connection) that declares the components of its
/// configuration (resources/demlink_fmu.cfg) at fmi2ExitInitializationMode and makes ONE
/// DataPackage exchange per fmi2DoStep(t, h). In the default order (send first) it sends
/// the inputs set for t, then receives the outputs of [t, t + h]: after the step the
/// outputs are those at t + h, as FMI 2.0 Co-Simulation defines them. The receive-first
/// order (configuration `exchange_order = receive_first`) receives [t - h, t] before sending:
/// one interval of lag, but a master that steps several DEMLink FMUs of one server in one
/// thread needs it (each send-first step waits for the other FMUs' inputs; docs/fmi.md).
/// Nothing waits for Compiled before the first step, so initializing several FMUs of one
/// server in one thread does not block.
#include <cctype>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "demlink/demlink_c.h"
#include "fmi2.h"
#include "fmu_config.hpp"

namespace {

using demlink::fmu::Causality;
using demlink::fmu::ComponentSpec;
using demlink::fmu::ExchangeOrder;
using demlink::fmu::FmuConfig;
using demlink::fmu::Slot;
using demlink::fmu::Variable;
using demlink::fmu::VariableType;

constexpr const char* kConfigFile = "demlink_fmu.cfg";
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

enum class Phase { kInstantiated, kInitialization, kStepping, kTerminated, kError };

/// Value references of one component's inputs and outputs, in layout order.
struct ComponentVariables {
  std::vector<fmi2ValueReference> input_reals;
  std::vector<fmi2ValueReference> output_ints;
  std::vector<fmi2ValueReference> output_reals;
};

struct Instance {
  std::string name;
  fmi2CallbackFunctions functions{};
  bool logging = false;
  FmuConfig config;
  std::vector<Variable> variables;
  std::vector<double> reals;         ///< by value reference
  std::vector<int> integers;         ///< by value reference
  std::vector<std::string> strings;  ///< by value reference
  std::vector<Slot> real_slots, integer_slots, string_slots;
  std::vector<ComponentVariables> components;  ///< by configuration index
  dl_client* client = nullptr;
  dl_package* package = nullptr;
  Phase phase = Phase::kInstantiated;
  double time = 0.0;
  bool first_step = true;
  bool server_finished = false;  ///< the DEM run ended (an end time, another client's fault)
};

void log(const Instance& instance, fmi2Status status, const char* category, const std::string& message) {
  if (instance.functions.logger == nullptr) return;
  // The logger formats like printf: a '%' in a server message must not be read as a directive.
  std::string escaped;
  for (char ch : message) {
    escaped.push_back(ch);
    if (ch == '%') escaped.push_back('%');
  }
  instance.functions.logger(instance.functions.componentEnvironment, instance.name.c_str(), status, category,
                            escaped.c_str());
}

fmi2Status fail(Instance& instance, const std::string& message) {
  instance.phase = Phase::kError;
  log(instance, fmi2Error, "logStatusError", message);
  return fmi2Error;
}

/// A DEMLink call's failure with the client's message. A finished DEM run is fmi2Discard
/// with fmi2Terminated set (the master may stop), not an error of the FMU.
fmi2Status failCall(Instance& instance, const char* call, int status) {
  if (status == DL_ERR_FINISHED && instance.phase == Phase::kStepping) {
    instance.server_finished = true;
    log(instance, fmi2Discard, "logStatusDiscard",
        std::string("the DEM run has ended: ") + dl_finished_reason(instance.client));
    return fmi2Discard;
  }
  std::string message = std::string(call) + " failed (status " + std::to_string(status) + ")";
  if (instance.client != nullptr) message += ": " + std::string(dl_last_error(instance.client));
  return fail(instance, message);
}

/// The directory of a "file:" resource URI (file:///abs, file:/abs, or a plain path).
std::string pathOfUri(std::string uri) {
  if (uri.rfind("file://", 0) == 0) {
    uri.erase(0, 7);
    if (!uri.empty() && uri[0] != '/') uri.erase(0, uri.find('/'));  // file://host/path
  } else if (uri.rfind("file:", 0) == 0) {
    uri.erase(0, 5);
  }
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size()) {
      out.push_back(static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(uri[i]);
    }
  }
  while (out.size() > 1 && out.back() == '/') out.pop_back();
#if defined(_WIN32)
  // file:///C:/dir names the path C:/dir.
  if (out.size() >= 3 && out[0] == '/' && std::isalpha(static_cast<unsigned char>(out[1])) && out[2] == ':') {
    out.erase(0, 1);
  }
#endif
  return out;
}

void setUpVariables(Instance& instance) {
  instance.variables = demlink::fmu::variablesOf(instance.config);
  instance.components.assign(instance.config.components.size(), {});
  for (const Variable& v : instance.variables) {
    switch (v.type) {
      case VariableType::kReal:
        instance.reals.push_back(v.start);
        instance.real_slots.push_back(v.slot);
        if (v.slot == Slot::kInputReal) instance.components[v.component].input_reals.push_back(v.value_reference);
        if (v.slot == Slot::kOutputReal) instance.components[v.component].output_reals.push_back(v.value_reference);
        break;
      case VariableType::kInteger:
        instance.integers.push_back(static_cast<int>(v.start));
        instance.integer_slots.push_back(v.slot);
        if (v.slot == Slot::kOutputInt) instance.components[v.component].output_ints.push_back(v.value_reference);
        break;
      case VariableType::kString:
        instance.strings.push_back(v.start_text);
        instance.string_slots.push_back(v.slot);
        break;
    }
  }
}

const std::string& stringParameter(const Instance& instance, Slot slot) {
  for (std::size_t vr = 0; vr < instance.string_slots.size(); ++vr) {
    if (instance.string_slots[vr] == slot) return instance.strings[vr];
  }
  throw std::logic_error("missing string parameter");
}

template <class T>
T scalarParameter(const Instance& instance, Slot slot, const std::vector<Slot>& slots, const std::vector<T>& values) {
  for (std::size_t vr = 0; vr < slots.size(); ++vr) {
    if (slots[vr] == slot) return values[vr];
  }
  (void)instance;
  throw std::logic_error("missing parameter");
}

/// The declare package of one component (generic layout): the configured lists with the
/// FMU's interval, the box's expected count and a body's initial pose from its inputs.
int sendDeclaration(Instance& instance, std::size_t index) {
  const ComponentSpec& c = instance.config.components[index];
  const bool exchanged = demlink::fmu::isExchanged(c.kind);
  std::vector<double> reals{exchanged ? instance.config.interval_s : 0.0};
  reals.insert(reals.end(), c.reals.begin(), c.reals.end());
  std::vector<long long> ints = c.ints;
  if (c.kind == "simulation_box") {
    if (reals.size() < 2) reals.push_back(kNaN);
    if (reals.size() < 3) reals.push_back(0.0);  // end time 0: the run ends when the FMU says Bye
    if (ints.empty()) ints.push_back(static_cast<long long>(instance.config.components.size()));
  }
  if (c.kind == "rigid_body") {
    if (reals.size() < 11) reals.resize(11, 0.0);
    const std::vector<fmi2ValueReference>& in = instance.components[index].input_reals;
    for (int i = 0; i < 7; ++i) reals[4 + static_cast<std::size_t>(i)] = instance.reals[in[static_cast<std::size_t>(i)]];
  }
  std::vector<const char*> strings{c.kind.c_str(), c.name.c_str()};
  for (const std::string& s : c.strings) strings.push_back(s.c_str());
  int status = dl_set_data(instance.package, ints.data(), static_cast<int>(ints.size()), reals.data(),
                           static_cast<int>(reals.size()), strings.data(), static_cast<int>(strings.size()));
  if (status == DL_OK) status = dl_send_package(instance.client, instance.package);
  return status;
}

/// Copies the output package in instance.package to the component's output variables.
fmi2Status storeOutputs(Instance& instance) {
  long long head[64];
  double values[64];
  int nInts = 0;
  int nReals = 0;
  int status = dl_get_ints(instance.package, head, 64, &nInts);
  if (status == DL_OK) status = dl_get_reals(instance.package, values, 64, &nReals);
  if (status != DL_OK) return failCall(instance, "reading an output package", status);
  if (nInts < 2 || head[0] < 0 || static_cast<std::size_t>(head[0]) >= instance.components.size()) {
    return fail(instance, "an output package names no component of this FMU");
  }
  const ComponentVariables& c = instance.components[static_cast<std::size_t>(head[0])];
  for (std::size_t i = 0; i < c.output_ints.size() && static_cast<int>(i) + 2 < nInts; ++i) {
    instance.integers[c.output_ints[i]] = static_cast<int>(head[i + 2]);
  }
  for (std::size_t i = 0; i < c.output_reals.size() && static_cast<int>(i) < nReals; ++i) {
    instance.reals[c.output_reals[i]] = values[i];
  }
  return fmi2OK;
}

/// Sends the inputs of every exchanged component for the FMU's time.
fmi2Status sendInputs(Instance& instance) {
  for (std::size_t i = 0; i < instance.config.components.size(); ++i) {
    if (!demlink::fmu::isExchanged(instance.config.components[i].kind)) continue;
    const long long handle = static_cast<long long>(i);
    std::vector<double> inputs;
    for (fmi2ValueReference vr : instance.components[i].input_reals) inputs.push_back(instance.reals[vr]);
    int status = dl_set_data(instance.package, &handle, 1, inputs.data(), static_cast<int>(inputs.size()), nullptr, 0);
    if (status == DL_OK) status = dl_send_package(instance.client, instance.package);
    if (status != DL_OK) return failCall(instance, "dl_send_package", status);
  }
  return fmi2OK;
}

/// Receives one answer per exchanged component (each the interval its last send began).
fmi2Status receiveOutputs(Instance& instance) {
  for (const ComponentSpec& c : instance.config.components) {
    if (!demlink::fmu::isExchanged(c.kind)) continue;
    if (const int status = dl_recv_package(instance.client, instance.package); status != DL_OK) {
      return failCall(instance, "dl_recv_package", status);
    }
    if (storeOutputs(instance) != fmi2OK) return fmi2Error;
  }
  return fmi2OK;
}

/// The initial outputs of Compiled (the receive-first order's first step).
fmi2Status storeInitialOutputs(Instance& instance) {
  if (const int status = dl_wait_compiled(instance.client); status != DL_OK) {
    return failCall(instance, "dl_wait_compiled", status);
  }
  for (std::size_t i = 0; i < instance.config.components.size(); ++i) {
    if (!demlink::fmu::isExchanged(instance.config.components[i].kind)) continue;
    if (const int status = dl_get_outputs(instance.client, static_cast<int>(i), instance.package); status != DL_OK) {
      return failCall(instance, "dl_get_outputs", status);
    }
    if (storeOutputs(instance) != fmi2OK) return fmi2Error;
  }
  return fmi2OK;
}

/// One DataPackage exchange per step in the configured order (top of this file).
fmi2Status exchange(Instance& instance) {
  if (instance.config.exchange_order == ExchangeOrder::kSendFirst) {
    if (const fmi2Status status = sendInputs(instance); status != fmi2OK) return status;
    return receiveOutputs(instance);
  }
  const fmi2Status received = instance.first_step ? storeInitialOutputs(instance) : receiveOutputs(instance);
  if (received != fmi2OK) return received;
  instance.first_step = false;
  return sendInputs(instance);
}

Instance* asInstance(fmi2Component c) { return static_cast<Instance*>(c); }

template <class Body>
fmi2Status guarded(fmi2Component c, Body&& body) {
  Instance* instance = asInstance(c);
  if (instance == nullptr) return fmi2Error;
  try {
    return body(*instance);
  } catch (const std::exception& e) {
    return fail(*instance, e.what());
  } catch (...) {
    return fail(*instance, "unknown error");
  }
}

/// True when a value reference of `type` is valid and may be set now.
fmi2Status checkSet(Instance& instance, const std::vector<Slot>& slots, fmi2ValueReference vr) {
  if (vr >= slots.size()) return fail(instance, "value reference " + std::to_string(vr) + " is unknown");
  const Slot slot = slots[vr];
  if (slot == Slot::kOutputInt || slot == Slot::kOutputReal) {
    return fail(instance, "value reference " + std::to_string(vr) + " is an output and cannot be set");
  }
  const bool parameter = slot != Slot::kInputReal;
  if (parameter && instance.phase != Phase::kInstantiated && instance.phase != Phase::kInitialization) {
    return fail(instance, "parameters can only be set before fmi2ExitInitializationMode");
  }
  return fmi2OK;
}

template <class T, class Out>
fmi2Status getValues(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, Out value[],
                     std::vector<T> Instance::*values) {
  return guarded(c, [&](Instance& instance) {
    const std::vector<T>& all = instance.*values;
    for (size_t i = 0; i < nvr; ++i) {
      if (vr[i] >= all.size()) return fail(instance, "value reference " + std::to_string(vr[i]) + " is unknown");
      if constexpr (std::is_same_v<T, std::string>) {
        value[i] = all[vr[i]].c_str();
      } else {
        value[i] = static_cast<Out>(all[vr[i]]);
      }
    }
    return fmi2OK;
  });
}

}  // namespace

extern "C" {

const char* fmi2GetTypesPlatform(void) { return "default"; }
const char* fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t, const fmi2String[]) {
  return guarded(c, [&](Instance& instance) {
    instance.logging = loggingOn != fmi2False;
    return fmi2OK;
  });
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions* functions,
                              fmi2Boolean, fmi2Boolean loggingOn) {
  Instance* instance = new (std::nothrow) Instance;
  if (instance == nullptr) return nullptr;
  instance->name = instanceName != nullptr ? instanceName : "";
  if (functions != nullptr) instance->functions = *functions;
  instance->logging = loggingOn != fmi2False;
  try {
    if (fmuType != fmi2CoSimulation) throw std::invalid_argument("this FMU supports Co-Simulation only");
    if (fmuResourceLocation == nullptr) throw std::invalid_argument("no resource location");
    const std::string text = demlink::fmu::readFile(pathOfUri(fmuResourceLocation) + "/" + kConfigFile);
    const std::string guid = demlink::fmu::guidOf(text);
    if (fmuGUID == nullptr || guid != fmuGUID) {
      throw std::invalid_argument("GUID " + std::string(fmuGUID != nullptr ? fmuGUID : "(null)") +
                                  " does not match the FMU's configuration (" + guid + ")");
    }
    instance->config = demlink::fmu::parseConfig(text);
    setUpVariables(*instance);
    instance->client = dl_client_create();
    instance->package = dl_package_create();
    if (instance->client == nullptr || instance->package == nullptr) throw std::bad_alloc();
    return instance;
  } catch (const std::exception& e) {
    log(*instance, fmi2Error, "logStatusError", std::string("fmi2Instantiate: ") + e.what());
    dl_package_destroy(instance->package);
    dl_client_destroy(instance->client);
    delete instance;
    return nullptr;
  }
}

void fmi2FreeInstance(fmi2Component c) {
  Instance* instance = asInstance(c);
  if (instance == nullptr) return;
  dl_package_destroy(instance->package);
  dl_client_destroy(instance->client);  // closes the connection (a Bye was sent by fmi2Terminate)
  delete instance;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean, fmi2Real, fmi2Real startTime, fmi2Boolean, fmi2Real) {
  return guarded(c, [&](Instance& instance) {
    if (instance.phase != Phase::kInstantiated) return fail(instance, "fmi2SetupExperiment after initialization");
    instance.time = startTime;
    return fmi2OK;
  });
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  return guarded(c, [&](Instance& instance) {
    if (instance.phase != Phase::kInstantiated) return fail(instance, "fmi2EnterInitializationMode twice");
    instance.phase = Phase::kInitialization;
    return fmi2OK;
  });
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  return guarded(c, [&](Instance& instance) {
    if (instance.phase != Phase::kInitialization) return fail(instance, "fmi2ExitInitializationMode outside initialization");
    const double timeout = scalarParameter(instance, Slot::kTimeout, instance.real_slots, instance.reals);
    const int port = scalarParameter(instance, Slot::kPort, instance.integer_slots, instance.integers);
    int status = dl_set_timeout(instance.client, timeout);
    if (status != DL_OK) return failCall(instance, "dl_set_timeout", status);
    status = dl_connect_to_host(instance.client, stringParameter(instance, Slot::kHost).c_str(), port,
                                instance.config.client_name.c_str(), stringParameter(instance, Slot::kToken).c_str());
    if (status != DL_OK) return failCall(instance, "dl_connect_to_host", status);
    for (std::size_t i = 0; i < instance.config.components.size(); ++i) {
      status = sendDeclaration(instance, i);
      if (status != DL_OK) {
        return failCall(instance, ("declaring '" + instance.config.components[i].name + "'").c_str(), status);
      }
    }
    instance.phase = Phase::kStepping;
    return fmi2OK;
  });
}

fmi2Status fmi2Terminate(fmi2Component c) {
  return guarded(c, [&](Instance& instance) {
    if (instance.phase == Phase::kStepping) {
      // Bye without waiting for Finished: other FMUs of the same server in this thread
      // still have to say theirs. The run ends when every declaring client said Bye.
      if (const int status = dl_finish(instance.client, "fmi2Terminate"); status != DL_OK) {
        return failCall(instance, "dl_finish", status);
      }
    }
    instance.phase = Phase::kTerminated;
    return fmi2OK;
  });
}

fmi2Status fmi2Reset(fmi2Component c) {
  return guarded(c, [&](Instance& instance) {
    if (instance.phase == Phase::kStepping) dl_finish(instance.client, "fmi2Reset");
    dl_client_destroy(instance.client);
    instance.client = dl_client_create();
    if (instance.client == nullptr) throw std::bad_alloc();
    instance.reals.clear();
    instance.integers.clear();
    instance.strings.clear();
    instance.real_slots.clear();
    instance.integer_slots.clear();
    instance.string_slots.clear();
    setUpVariables(instance);
    instance.phase = Phase::kInstantiated;
    instance.first_step = true;
    instance.time = 0.0;
    return fmi2OK;
  });
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
  return getValues<double, fmi2Real>(c, vr, nvr, value, &Instance::reals);
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
  return getValues<int, fmi2Integer>(c, vr, nvr, value, &Instance::integers);
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
  return getValues<std::string, fmi2String>(c, vr, nvr, value, &Instance::strings);
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference[], size_t nvr, fmi2Boolean[]) {
  return guarded(c, [&](Instance& instance) { return nvr == 0 ? fmi2OK : fail(instance, "this FMU has no Boolean variables"); });
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
  return guarded(c, [&](Instance& instance) {
    for (size_t i = 0; i < nvr; ++i) {
      if (checkSet(instance, instance.real_slots, vr[i]) != fmi2OK) return fmi2Error;
      if (!std::isfinite(value[i])) {
        return fail(instance, "value reference " + std::to_string(vr[i]) + ": " + std::to_string(value[i]) +
                                  " is not finite");
      }
      instance.reals[vr[i]] = value[i];
    }
    return fmi2OK;
  });
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
  return guarded(c, [&](Instance& instance) {
    for (size_t i = 0; i < nvr; ++i) {
      if (checkSet(instance, instance.integer_slots, vr[i]) != fmi2OK) return fmi2Error;
      instance.integers[vr[i]] = value[i];
    }
    return fmi2OK;
  });
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
  return guarded(c, [&](Instance& instance) {
    for (size_t i = 0; i < nvr; ++i) {
      if (checkSet(instance, instance.string_slots, vr[i]) != fmi2OK) return fmi2Error;
      instance.strings[vr[i]] = value[i] != nullptr ? value[i] : "";
    }
    return fmi2OK;
  });
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2Boolean[]) {
  return guarded(c, [&](Instance& instance) { return nvr == 0 ? fmi2OK : fail(instance, "this FMU has no Boolean variables"); });
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate*) {
  return guarded(c, [](Instance& instance) { return fail(instance, "canGetAndSetFMUstate is false"); });
}
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate) { return fmi2GetFMUstate(c, nullptr); }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate*) { return fmi2GetFMUstate(c, nullptr); }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate, size_t*) { return fmi2GetFMUstate(c, nullptr); }
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate, fmi2Byte[], size_t) {
  return fmi2GetFMUstate(c, nullptr);
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte[], size_t, fmi2FMUstate*) {
  return fmi2GetFMUstate(c, nullptr);
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference[], size_t,
                                        const fmi2ValueReference[], size_t, const fmi2Real[], fmi2Real[]) {
  return guarded(c, [](Instance& instance) { return fail(instance, "providesDirectionalDerivative is false"); });
}
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t, const fmi2Integer[],
                                       const fmi2Real[]) {
  return guarded(c, [](Instance& instance) { return fail(instance, "canInterpolateInputs is false"); });
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t, const fmi2Integer[],
                                        fmi2Real[]) {
  return guarded(c, [](Instance& instance) { return fail(instance, "maxOutputDerivativeOrder is 0"); });
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean) {
  return guarded(c, [&](Instance& instance) {
    if (instance.phase != Phase::kStepping) return fail(instance, "fmi2DoStep outside the stepping phase");
    const double h = instance.config.interval_s;
    if (std::fabs(communicationStepSize - h) > 1e-9 * h) {
      return fail(instance, "communicationStepSize " + std::to_string(communicationStepSize) +
                                " s differs from the FMU's communication interval " + std::to_string(h) +
                                " s (one DataPackage exchange per step)");
    }
    if (std::fabs(currentCommunicationPoint - instance.time) > 1e-6 * h) {
      return fail(instance, "currentCommunicationPoint " + std::to_string(currentCommunicationPoint) +
                                " s is not the FMU's time " + std::to_string(instance.time) + " s");
    }
    if (instance.server_finished) return fmi2Discard;
    if (const fmi2Status status = exchange(instance); status != fmi2OK) return status;
    instance.time = currentCommunicationPoint + communicationStepSize;
    return fmi2OK;
  });
}

fmi2Status fmi2CancelStep(fmi2Component c) {
  return guarded(c, [](Instance& instance) { return fail(instance, "fmi2DoStep never returns fmi2Pending"); });
}
fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind, fmi2Status*) {
  return guarded(c, [](Instance& instance) { return fail(instance, "fmi2DoStep is synchronous"); });
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real* value) {
  return guarded(c, [&](Instance& instance) {
    if (s != fmi2LastSuccessfulTime || value == nullptr) return fail(instance, "only fmi2LastSuccessfulTime is a Real status");
    *value = instance.time;
    return fmi2OK;
  });
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind, fmi2Integer*) { return fmi2GetStatus(c, {}, nullptr); }
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean* value) {
  return guarded(c, [&](Instance& instance) {
    if (s != fmi2Terminated || value == nullptr) return fail(instance, "only fmi2Terminated is a Boolean status");
    *value = instance.phase == Phase::kTerminated || instance.server_finished ? fmi2True : fmi2False;
    return fmi2OK;
  });
}
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind, fmi2String*) { return fmi2GetStatus(c, {}, nullptr); }

}  // extern "C"
