#pragma once
/// The DEMLink FMU's configuration (docs/fmi.md): which components the FMU declares on the
/// server, and the FMI variables that follow from them. Shared by the packaging tool
/// (demlink-fmu writes modelDescription.xml from it) and the FMU library (which reads the
/// same file from the FMU's resources), so both number the variables identically.
///
/// File format ('#' starts a comment; docs/fmi.md "Configuration"): first the FMU's
/// statements, one `key = value` per line:
///   model = IDENTIFIER          C identifier: the FMU's modelIdentifier and library name
///   description = TEXT          (optional)
///   host / port / token / timeout / client_name = ...   (parameter defaults)
///   interval = SECONDS          communication interval = the FMU's communication step
///   exchange_order = ORDER      send_first (default) or receive_first (docs/fmi.md, "Timing")
/// then one section per component: a line `[KIND NAME]` and its fields, one `field = value`
/// per line (the fields of each kind, their units and their place in the C ABI's generic
/// declare layout: fmu_fields.cpp). A vector is its numbers separated by spaces.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace demlink::fmu {

/// One declared component in the generic layout.
struct ComponentSpec {
  std::string kind;
  std::string name;
  std::vector<long long> ints;
  std::vector<double> reals;         ///< declare reals[1..]
  std::vector<std::string> strings;  ///< declare strings[2..]
};

/// When fmi2DoStep(t, h) sends and receives (docs/fmi.md, "Timing").
enum class ExchangeOrder {
  kSendFirst,     ///< send the inputs at t, receive [t, t + h]: outputs at t + h (FMI 2.0)
  kReceiveFirst,  ///< receive [t - h, t], then send: one interval of lag; several FMUs of one server in one thread
};

struct FmuConfig {
  std::string model_identifier;
  std::string description;
  std::string host = "127.0.0.1";
  int port = 47000;
  std::string token;
  std::string client_name;  ///< "" : the model identifier
  double timeout_s = 30.0;
  double interval_s = 0.0;  ///< communication interval [s]
  ExchangeOrder exchange_order = ExchangeOrder::kSendFirst;
  std::vector<ComponentSpec> components;
};

enum class VariableType { kReal, kInteger, kString };
enum class Causality { kParameter, kInput, kOutput };

/// Where a variable's value goes to or comes from.
enum class Slot {
  kHost,
  kPort,
  kToken,
  kTimeout,
  kInputReal,   ///< the component's input package reals[index]
  kOutputInt,   ///< the component's output package ints[2 + index]
  kOutputReal,  ///< the component's output package reals[index]
};

struct Variable {
  std::string name;
  std::string description;
  VariableType type = VariableType::kReal;
  std::string unit;  ///< of a Real ("" none)
  Causality causality = Causality::kOutput;
  std::uint32_t value_reference = 0;  ///< unique within its type (FMI 2.0 numbers each type apart)
  double start = 0.0;                 ///< Real / Integer parameters and inputs
  std::string start_text;             ///< String parameters
  Slot slot = Slot::kOutputReal;
  int component = -1;  ///< index into FmuConfig::components
  int index = 0;       ///< index within the slot's array
};

/// One input or output of an exchanged kind: its name within the component, SI unit
/// (modelDescription's unit; "" for counts, which FMI 2.0 Integers cannot carry) and meaning.
struct Signal {
  std::string name;
  std::string unit;
  std::string description;
};

/// Inputs and outputs of an exchanged kind, in the generic input/output layout's order.
struct KindLayout {
  std::vector<Signal> input_reals;
  std::vector<Signal> output_ints;
  std::vector<Signal> output_reals;
};

/// True for the kinds the FMU exchanges every step; false for declared-only kinds.
/// Throws std::invalid_argument for kinds the FMU cannot carry.
bool isExchanged(const std::string& kind);
/// The layout of an exchanged kind.
const KindLayout& layoutOf(const std::string& kind);

/// Parses the file format above; std::invalid_argument names the line, field and value.
FmuConfig parseConfig(std::string_view text);
/// A file's bytes; std::invalid_argument naming the path when it cannot be read.
std::string readFile(const std::string& path);
/// Reads and parses a file; std::invalid_argument when it cannot be read.
FmuConfig readConfigFile(const std::string& path);
/// Every FMI variable in modelDescription order (parameters, then per component).
std::vector<Variable> variablesOf(const FmuConfig& config);
/// A stable GUID of the configuration text ("{xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx}").
std::string guidOf(std::string_view configText);
/// The units modelDescription.xml declares (UnitDefinitions): name and the exponents of the
/// SI base units kg, m, s, rad in that order.
struct UnitDefinition {
  const char* name;
  int kg, m, s, rad;
};
const std::vector<UnitDefinition>& unitDefinitions();
/// modelDescription.xml for the configuration.
std::string modelDescriptionXml(const FmuConfig& config, const std::string& guid);

}  // namespace demlink::fmu
