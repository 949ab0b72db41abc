#pragma once
/// The DEMLink FMU's configuration (docs/fmi.md): which components the FMU declares on the
/// server, and the FMI variables that follow from them. Shared by the packaging tool
/// (demlink-fmu writes modelDescription.xml from it) and the FMU library (which reads the
/// same file from the FMU's resources), so both number the variables identically.
///
/// File format, one statement per line ('#' starts a comment):
///   model IDENTIFIER            C identifier: the FMU's modelIdentifier and library name
///   description TEXT            (optional)
///   host HOST / port N / token T / timeout SECONDS / client_name NAME   (parameter defaults)
///   interval SECONDS            communication interval = the FMU's communication step
///   component KIND NAME [ints=i,i,...] [reals=r,r,...] [strings=s,s,...]
/// A component's lists are the generic declare layout of docs/c_abi.md without its fixed
/// prefix: ints from ints[0], reals from reals[1] (reals[0] is the interval, set by the FMU),
/// strings from strings[2] (kind and name come first). "nan" is a real ("not given").
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

struct FmuConfig {
  std::string model_identifier;
  std::string description;
  std::string host = "127.0.0.1";
  int port = 47000;
  std::string token;
  std::string client_name;  ///< "" : the model identifier
  double timeout_s = 30.0;
  double interval_s = 0.0;  ///< communication interval [s]
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
  Causality causality = Causality::kOutput;
  std::uint32_t value_reference = 0;  ///< unique within its type (FMI 2.0 numbers each type apart)
  double start = 0.0;                 ///< Real / Integer parameters and inputs
  std::string start_text;             ///< String parameters
  Slot slot = Slot::kOutputReal;
  int component = -1;  ///< index into FmuConfig::components
  int index = 0;       ///< index within the slot's array
};

/// Input and output names of an exchanged kind (the generic input/output layout).
struct KindLayout {
  std::vector<std::string> input_reals;
  std::vector<std::string> output_ints;
  std::vector<std::string> output_reals;
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
/// modelDescription.xml for the configuration.
std::string modelDescriptionXml(const FmuConfig& config, const std::string& guid);

}  // namespace demlink::fmu
