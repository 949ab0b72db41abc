/// Parsing of the FMU configuration, its FMI variables and modelDescription.xml.
#include "fmu_config.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace demlink::fmu {
namespace {

std::vector<std::string> expand(const std::string& name, int n) {
  std::vector<std::string> out;
  for (int i = 1; i <= n; ++i) out.push_back(name + "[" + std::to_string(i) + "]");
  return out;
}

std::vector<std::string> join(std::initializer_list<std::vector<std::string>> parts) {
  std::vector<std::string> out;
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

/// The generic output/input layouts of docs/c_abi.md, named.
const std::map<std::string, KindLayout>& layouts() {
  static const std::map<std::string, KindLayout> table = {
      {"simulation_box",
       {expand("gravity", 3), {"particleCount"}, {"time", "totalMass", "kineticEnergy", "stepRate"}}},
      {"rigid_body",
       {join({expand("position", 3), expand("orientation", 4), expand("velocity", 3), expand("angularVelocity", 3)}),
        {},
        join({expand("meanForce", 3), expand("meanTorque", 3), expand("force", 3), expand("torque", 3),
              expand("bodyPosition", 3), expand("bodyOrientation", 4)})}},
      {"particle_source",
       {{}, {"count", "countTotal", "shortfallTotal"}, {"mass", "massTotal", "shortfallMassTotal"}}},
      {"particle_sink", {{}, {"count", "countTotal"}, {"mass", "massTotal"}}},
      {"region_sensor", {{}, {"count"}, join({{"mass"}, expand("centreOfMass", 3), expand("meanVelocity", 3)})}},
      {"flow_sensor",
       {{},
        {"positiveCount", "negativeCount", "positiveCountTotal", "negativeCountTotal"},
        {"positiveMass", "negativeMass", "positiveMassTotal", "negativeMassTotal"}}},
  };
  return table;
}

const char* const kDeclaredOnly[] = {"material", "plane", "single_particle", "particle_system", "pit_generator"};

[[noreturn]] void bad(int line, const std::string& field, const std::string& value, const std::string& reason) {
  throw std::invalid_argument("FMU configuration line " + std::to_string(line) + ": " + field + " = '" + value +
                              "': " + reason);
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::string item;
  for (char ch : text) {
    if (ch == ',') {
      out.push_back(item);
      item.clear();
    } else {
      item.push_back(ch);
    }
  }
  out.push_back(item);
  return out;
}

double parseReal(int line, const std::string& field, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) bad(line, field, text, "not a number");
  return value;
}

long long parseInt(int line, const std::string& field, const std::string& text) {
  char* end = nullptr;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size()) bad(line, field, text, "not an integer");
  return value;
}

bool isIdentifier(const std::string& text) {
  if (text.empty() || (std::isdigit(static_cast<unsigned char>(text[0])) != 0)) return false;
  for (char ch : text) {
    if (std::isalnum(static_cast<unsigned char>(ch)) == 0 && ch != '_') return false;
  }
  return true;
}

std::string xmlEscape(const std::string& text) {
  std::string out;
  for (char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out.push_back(ch);
    }
  }
  return out;
}

std::string realText(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

/// reals[i] of a component's declare layout (index as in docs/c_abi.md), or `fallback`.
double declared(const ComponentSpec& c, std::size_t layoutIndex, double fallback) {
  const std::size_t i = layoutIndex - 1;
  return i < c.reals.size() && std::isfinite(c.reals[i]) ? c.reals[i] : fallback;
}

/// Start values of a component's inputs: its declared initial state.
double inputStart(const ComponentSpec& c, int index) {
  if (c.kind == "simulation_box") return declared(c, 3 + static_cast<std::size_t>(index), index == 2 ? -9.81 : 0.0);
  if (c.kind == "rigid_body" && index < 7) return declared(c, 4 + static_cast<std::size_t>(index), index == 3 ? 1.0 : 0.0);
  return 0.0;
}

}  // namespace

bool isExchanged(const std::string& kind) {
  if (layouts().contains(kind)) return true;
  for (const char* only : kDeclaredOnly) {
    if (kind == only) return false;
  }
  throw std::invalid_argument("component kind '" + kind +
                              "' cannot be carried by an FMU (exchanged: simulation_box, rigid_body, particle_source, "
                              "particle_sink, region_sensor, flow_sensor; declared only: material, plane, "
                              "single_particle, particle_system, pit_generator)");
}

const KindLayout& layoutOf(const std::string& kind) { return layouts().at(kind); }

FmuConfig parseConfig(std::string_view text) {
  FmuConfig config;
  std::istringstream in{std::string(text)};
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    if (const std::size_t hash = raw.find('#'); hash != std::string::npos) raw.erase(hash);
    std::istringstream words(raw);
    std::string key;
    if (!(words >> key)) continue;
    std::string rest;
    std::getline(words >> std::ws, rest);
    while (!rest.empty() && std::isspace(static_cast<unsigned char>(rest.back())) != 0) rest.pop_back();
    if (key == "model") {
      if (!isIdentifier(rest)) bad(line, "model", rest, "must be a C identifier (letters, digits, _)");
      config.model_identifier = rest;
    } else if (key == "description") {
      config.description = rest;
    } else if (key == "host") {
      config.host = rest;
    } else if (key == "port") {
      config.port = static_cast<int>(parseInt(line, "port", rest));
      if (config.port <= 0 || config.port > 65535) bad(line, "port", rest, "must be in 1..65535");
    } else if (key == "token") {
      config.token = rest;
    } else if (key == "client_name") {
      config.client_name = rest;
    } else if (key == "timeout") {
      config.timeout_s = parseReal(line, "timeout", rest);
      if (!(config.timeout_s > 0.0)) bad(line, "timeout", rest, "must be > 0");
    } else if (key == "interval") {
      config.interval_s = parseReal(line, "interval", rest);
      if (!(config.interval_s > 0.0) || !std::isfinite(config.interval_s)) bad(line, "interval", rest, "must be > 0");
    } else if (key == "component") {
      ComponentSpec c;
      std::istringstream parts(rest);
      if (!(parts >> c.kind >> c.name)) bad(line, "component", rest, "needs KIND NAME");
      try {
        (void)isExchanged(c.kind);
      } catch (const std::invalid_argument& e) {
        bad(line, "component kind", c.kind, e.what());
      }
      if (!isIdentifier(c.name)) bad(line, "component name", c.name, "must be an identifier (it names FMI variables)");
      for (const ComponentSpec& other : config.components) {
        if (other.name == c.name) bad(line, "component name", c.name, "declared twice");
      }
      std::string list;
      while (parts >> list) {
        const std::size_t eq = list.find('=');
        const std::string field = list.substr(0, eq);
        const std::string values = eq == std::string::npos ? "" : list.substr(eq + 1);
        if (field == "ints") {
          for (const std::string& v : splitList(values)) c.ints.push_back(parseInt(line, c.name + ".ints", v));
        } else if (field == "reals") {
          for (const std::string& v : splitList(values)) c.reals.push_back(parseReal(line, c.name + ".reals", v));
        } else if (field == "strings") {
          c.strings = splitList(values);
        } else {
          bad(line, c.name, list, "expected ints=..., reals=... or strings=...");
        }
      }
      config.components.push_back(std::move(c));
    } else {
      bad(line, "statement", key,
          "unknown (model, description, host, port, token, client_name, timeout, interval, component)");
    }
  }
  if (config.model_identifier.empty()) bad(line, "model", "", "missing");
  if (!(config.interval_s > 0.0)) bad(line, "interval", "", "missing");
  if (config.components.empty()) bad(line, "component", "", "no component declared");
  if (config.client_name.empty()) config.client_name = config.model_identifier;
  return config;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("cannot read '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

FmuConfig readConfigFile(const std::string& path) { return parseConfig(readFile(path)); }

std::vector<Variable> variablesOf(const FmuConfig& config) {
  std::vector<Variable> out;
  std::uint32_t nextReal = 0;
  std::uint32_t nextInt = 0;
  std::uint32_t nextString = 0;
  auto add = [&](Variable v) {
    v.value_reference = v.type == VariableType::kReal ? nextReal++ : v.type == VariableType::kInteger ? nextInt++ : nextString++;
    out.push_back(std::move(v));
  };
  add({"host", "Host of demlink-server", VariableType::kString, Causality::kParameter, 0, 0.0, config.host, Slot::kHost});
  add({"port", "TCP port of demlink-server", VariableType::kInteger, Causality::kParameter, 0,
       static_cast<double>(config.port), "", Slot::kPort});
  add({"token", "Access token (empty: none)", VariableType::kString, Causality::kParameter, 0, 0.0, config.token,
       Slot::kToken});
  add({"timeout", "Longest wait for the server in one call [s]", VariableType::kReal, Causality::kParameter, 0,
       config.timeout_s, "", Slot::kTimeout});
  for (std::size_t ci = 0; ci < config.components.size(); ++ci) {
    const ComponentSpec& c = config.components[ci];
    if (!isExchanged(c.kind)) continue;
    const KindLayout& layout = layoutOf(c.kind);
    const int component = static_cast<int>(ci);
    for (std::size_t i = 0; i < layout.input_reals.size(); ++i) {
      add({c.name + "." + layout.input_reals[i], c.kind + " input", VariableType::kReal, Causality::kInput, 0,
           inputStart(c, static_cast<int>(i)), "", Slot::kInputReal, component, static_cast<int>(i)});
    }
    for (std::size_t i = 0; i < layout.output_ints.size(); ++i) {
      add({c.name + "." + layout.output_ints[i], c.kind + " output (the interval that ended one step ago)",
           VariableType::kInteger, Causality::kOutput, 0, 0.0, "", Slot::kOutputInt, component, static_cast<int>(i)});
    }
    for (std::size_t i = 0; i < layout.output_reals.size(); ++i) {
      add({c.name + "." + layout.output_reals[i], c.kind + " output (the interval that ended one step ago)",
           VariableType::kReal, Causality::kOutput, 0, 0.0, "", Slot::kOutputReal, component, static_cast<int>(i)});
    }
  }
  return out;
}

std::string guidOf(std::string_view configText) {
  // FNV-1a, twice with different offsets: 128 bits that change with every byte of the text.
  std::uint64_t a = 14695981039346656037ull;
  std::uint64_t b = 1099511628211ull * 31u;
  for (char ch : configText) {
    a = (a ^ static_cast<unsigned char>(ch)) * 1099511628211ull;
    b = (b ^ static_cast<unsigned char>(ch)) * 1099511628211ull;
  }
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "{%08x-%04x-%04x-%04x-%012llx}", static_cast<unsigned>(a >> 32),
                static_cast<unsigned>((a >> 16) & 0xffffu), static_cast<unsigned>(a & 0xffffu),
                static_cast<unsigned>(b >> 48), static_cast<unsigned long long>(b & 0xffffffffffffull));
  return buffer;
}

std::string modelDescriptionXml(const FmuConfig& config, const std::string& guid) {
  const std::vector<Variable> variables = variablesOf(config);
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"" << xmlEscape(config.model_identifier) << "\" guid=\""
    << guid << "\" description=\"" << xmlEscape(config.description)
    << "\" generationTool=\"demlink-fmu\" variableNamingConvention=\"structured\" numberOfEventIndicators=\"0\">\n"
    << "  <CoSimulation modelIdentifier=\"" << config.model_identifier
    << "\" needsExecutionTool=\"true\" canHandleVariableCommunicationStepSize=\"false\""
       " canInterpolateInputs=\"false\" maxOutputDerivativeOrder=\"0\" canRunAsynchronuously=\"false\""
       " canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"true\""
       " canGetAndSetFMUstate=\"false\" canSerializeFMUstate=\"false\" providesDirectionalDerivative=\"false\"/>\n"
    << "  <DefaultExperiment startTime=\"0\" stepSize=\"" << realText(config.interval_s) << "\"/>\n"
    << "  <ModelVariables>\n";
  std::vector<std::size_t> outputs;
  for (std::size_t i = 0; i < variables.size(); ++i) {
    const Variable& v = variables[i];
    x << "    <ScalarVariable name=\"" << xmlEscape(v.name) << "\" valueReference=\"" << v.value_reference
      << "\" description=\"" << xmlEscape(v.description) << "\"";
    switch (v.causality) {
      case Causality::kParameter: x << " causality=\"parameter\" variability=\"fixed\" initial=\"exact\">"; break;
      case Causality::kInput: x << " causality=\"input\" variability=\"continuous\">"; break;
      case Causality::kOutput:
        x << " causality=\"output\" variability=\"discrete\" initial=\"calculated\">";
        outputs.push_back(i + 1);
        break;
    }
    const bool withStart = v.causality != Causality::kOutput;
    switch (v.type) {
      case VariableType::kReal: x << "<Real"; break;
      case VariableType::kInteger: x << "<Integer"; break;
      case VariableType::kString: x << "<String"; break;
    }
    if (withStart) {
      x << " start=\"";
      if (v.type == VariableType::kString) {
        x << xmlEscape(v.start_text);
      } else if (v.type == VariableType::kInteger) {
        x << static_cast<long long>(v.start);
      } else {
        x << realText(v.start);
      }
      x << "\"";
    }
    x << "/></ScalarVariable>\n";
  }
  x << "  </ModelVariables>\n  <ModelStructure>\n    <Outputs>\n";
  for (std::size_t index : outputs) x << "      <Unknown index=\"" << index << "\"/>\n";
  x << "    </Outputs>\n    <InitialUnknowns>\n";
  for (std::size_t index : outputs) x << "      <Unknown index=\"" << index << "\"/>\n";
  x << "    </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>\n";
  return x.str();
}

}  // namespace demlink::fmu
