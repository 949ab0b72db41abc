/// Parsing of the FMU configuration, its FMI variables and modelDescription.xml.
#include "fmu_config.hpp"

#include <algorithm>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "fmu_fields.hpp"

namespace demlink::fmu {
namespace {

/// `n` signals name[1..n] of one unit and meaning ("" n: the name alone).
std::vector<Signal> expand(const std::string& name, int n, const std::string& unit, const std::string& description) {
  std::vector<Signal> out;
  for (int i = 1; i <= n; ++i) out.push_back({name + "[" + std::to_string(i) + "]", unit, description});
  return out;
}

std::vector<Signal> join(std::initializer_list<std::vector<Signal>> parts) {
  std::vector<Signal> out;
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

/// The generic output/input layouts of docs/c_abi.md, named, with units (frames: world).
const std::map<std::string, KindLayout>& layouts() {
  static const std::map<std::string, KindLayout> table = {
      {"simulation_box",
       {expand("gravity", 3, "m/s2", "Gravity (x y z)"),
        {{"particleCount", "", "Particles in the DEM world"}},
        {{"time", "s", "DEM time at the end of the reported interval"},
         {"totalMass", "kg", "Mass of all particles"},
         {"kineticEnergy", "J", "Kinetic energy of all particles"},
         {"stepRate", "1/s", "DEM steps per wall-clock second"}}}},
      {"rigid_body",
       {join({expand("position", 3, "m", "Reference point's position sent"),
              expand("orientation", 4, "1", "Orientation sent, quaternion w x y z (body to world)"),
              expand("velocity", 3, "m/s", "Reference point's velocity sent"),
              expand("angularVelocity", 3, "rad/s", "Angular velocity sent")}),
        {},
        join({expand("meanForce", 3, "N", "Force of the particles on the body, mean over the interval"),
              expand("meanTorque", 3, "N.m", "Torque about the reference point, mean over the interval"),
              expand("force", 3, "N", "Force at the interval's end"),
              expand("torque", 3, "N.m", "Torque at the interval's end"),
              expand("bodyPosition", 3, "m", "Reference point's position at the interval's end"),
              expand("bodyOrientation", 4, "1", "Orientation at the interval's end, quaternion w x y z")})}},
      {"particle_source",
       {{},
        {{"count", "", "Particles inserted during the interval"},
         {"countTotal", "", "Particles inserted since the start"},
         {"shortfallTotal", "", "Particles that found no room since the start"}},
        {{"mass", "kg", "Mass inserted during the interval"},
         {"massTotal", "kg", "Mass inserted since the start"},
         {"shortfallMassTotal", "kg", "Mass that found no room since the start"}}}},
      {"particle_sink",
       {{},
        {{"count", "", "Particles removed during the interval"}, {"countTotal", "", "Particles removed since the start"}},
        {{"mass", "kg", "Mass removed during the interval"}, {"massTotal", "kg", "Mass removed since the start"}}}},
      {"region_sensor",
       {{},
        {{"count", "", "Particles in the region"},
         {"bondsIntact", "", "Intact parallel bonds whose midpoint is in the region"},
         {"bondsBroken", "", "Broken parallel bonds whose midpoint is in the region"}},
        join({{{"mass", "kg", "Mass in the region"}},
              expand("centreOfMass", 3, "m", "Centre of mass of the particles in the region (0 when empty)"),
              expand("meanVelocity", 3, "m/s", "Mean velocity of the particles in the region (0 when empty)")})}},
      {"flow_sensor",
       {{},
        {{"positiveCount", "", "Crossings along the normal during the interval"},
         {"negativeCount", "", "Crossings against the normal during the interval"},
         {"positiveCountTotal", "", "Crossings along the normal since the start"},
         {"negativeCountTotal", "", "Crossings against the normal since the start"}},
        {{"positiveMass", "kg", "Mass crossing along the normal during the interval"},
         {"negativeMass", "kg", "Mass crossing against the normal during the interval"},
         {"positiveMassTotal", "kg", "Mass crossing along the normal since the start"},
         {"negativeMassTotal", "kg", "Mass crossing against the normal since the start"}}}},
  };
  return table;
}

const char* const kDeclaredOnly[] = {"material",      "plane",          "single_particle", "particle_system",
                                     "pit_generator", "parallel_bonds", "clump_template"};

[[noreturn]] void bad(int line, const std::string& field, const std::string& value, const std::string& reason) {
  throw std::invalid_argument("FMU configuration line " + std::to_string(line) + ": " + field + " = '" + value +
                              "': " + reason);
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
                              "single_particle, particle_system, pit_generator, parallel_bonds, clump_template)");
}

const KindLayout& layoutOf(const std::string& kind) { return layouts().at(kind); }

namespace {

std::string trim(const std::string& text) {
  const std::size_t first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  const std::size_t last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::vector<std::string> words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> out;
  for (std::string word; in >> word;) out.push_back(word);
  return out;
}

const char* const kStatements = "model, description, host, port, token, client_name, timeout, interval, exchange_order";

/// True for a top-level statement's key.
bool isStatement(const std::string& key) {
  for (const std::string& statement : words(std::string(kStatements))) {
    if (statement == key + "," || statement == key) return true;
  }
  return false;
}

std::string fieldNames(const std::vector<FieldSpec>& fields) {
  std::string out;
  for (const FieldSpec& f : fields) out += (out.empty() ? "" : ", ") + std::string(f.name);
  return out;
}

/// One [kind name] section while it is read: the given fields' texts and lines.
struct Section {
  ComponentSpec spec;
  int line = 0;
  std::map<std::string, std::pair<int, std::string>> given;  ///< field -> (line, value text)
};

/// The number a choice field stands for (given, or its first choice when unset).
long long choiceValue(const Section& s, const FieldSpec& f) {
  const auto it = s.given.find(f.name);
  if (it == s.given.end()) return f.choices.front().second;
  for (const auto& [text, value] : f.choices) {
    if (it->second.second == text) return value;
  }
  return f.choices.front().second;  // unreachable: checked when the field was read
}

/// Checks one field's text; the error names the line, `component.field` and the value.
void checkField(const Section& s, const FieldSpec& f, int line, const std::string& value) {
  const std::string where = s.spec.name + "." + f.name;
  switch (f.type) {
    case FieldType::kReal: {
      const std::vector<std::string> parts = words(value);
      if (static_cast<int>(parts.size()) != f.count) {
        bad(line, where, value,
            "needs " + std::to_string(f.count) + (f.count == 1 ? " number" : " numbers separated by spaces") +
                (f.unit[0] != '\0' ? std::string(" [") + f.unit + "]" : std::string()) + ", got " +
                std::to_string(parts.size()));
      }
      for (const std::string& part : parts) {
        if (!std::isfinite(parseReal(line, where, part))) bad(line, where, value, "must be finite");
      }
      break;
    }
    case FieldType::kRealList: {
      const std::vector<std::string> parts = words(value);
      if (parts.empty() || parts.size() % static_cast<std::size_t>(f.count) != 0) {
        bad(line, where, value,
            "needs numbers in groups of " + std::to_string(f.count) + ", at least one group, got " +
                std::to_string(parts.size()));
      }
      for (const std::string& part : parts) {
        if (!std::isfinite(parseReal(line, where, part))) bad(line, where, value, "must be finite");
      }
      break;
    }
    case FieldType::kInteger:
      (void)parseInt(line, where, value);
      break;
    case FieldType::kChoice: {
      std::string names;
      for (const auto& [text, number] : f.choices) {
        if (value == text) return;
        names += (names.empty() ? "" : ", ") + std::string(text);
      }
      bad(line, where, value, "must be one of " + names);
    }
    case FieldType::kText:
    case FieldType::kTextList:
      break;
  }
}

/// The generic declare layout of a finished section (positions: fmu_fields.cpp).
void buildLayout(Section& s) {
  const std::vector<FieldSpec>& fields = fieldsOf(s.spec.kind);
  std::size_t nReals = 0;
  std::size_t nInts = 0;
  std::size_t nStrings = 0;
  for (const FieldSpec& f : fields) {
    const bool given = s.given.contains(f.name);
    if (f.required && !given) {
      bad(s.line, s.spec.name + "." + f.name, "", "missing (fields of " + s.spec.kind + ": " + fieldNames(fields) + ")");
    }
    if (given && f.requires_choice.first != nullptr) {
      const auto choice = std::find_if(fields.begin(), fields.end(),
                                       [&](const FieldSpec& c) { return std::string(c.name) == f.requires_choice.first; });
      const long long wanted = std::find_if(choice->choices.begin(), choice->choices.end(), [&](const auto& c) {
                                 return std::string(c.first) == f.requires_choice.second;
                               })->second;
      if (choiceValue(s, *choice) != wanted) {
        const auto& [line, value] = s.given.at(f.name);
        bad(line, s.spec.name + "." + f.name, value,
            std::string("is a field of ") + choice->name + " = " + f.requires_choice.second + " (set " + choice->name +
                " = " + f.requires_choice.second + ")");
      }
    }
    if (!given && f.defaults.empty()) continue;
    const std::size_t end = f.type == FieldType::kRealList
                                ? static_cast<std::size_t>(f.index) + words(s.given.at(f.name).second).size()
                                : static_cast<std::size_t>(f.index + f.count);
    if (f.array == FieldArray::kReals) nReals = std::max(nReals, end);
    if (f.array == FieldArray::kInts) nInts = std::max(nInts, end);
    if (f.array == FieldArray::kStrings) nStrings = std::max(nStrings, end);
  }
  // reals[0] is the interval: the spec holds reals[1..].
  s.spec.reals.assign(nReals > 0 ? nReals - 1 : 0, std::nan(""));
  s.spec.ints.assign(nInts, 0);
  s.spec.strings.assign(nStrings > 2 ? nStrings - 2 : 0, "");
  std::vector<std::string> owner(std::max(nReals, std::max(nInts, nStrings)) * 3);
  for (const FieldSpec& f : fields) {
    const auto it = s.given.find(f.name);
    if (f.array == FieldArray::kInts && f.type == FieldType::kChoice) {
      if (static_cast<std::size_t>(f.index) < nInts) s.spec.ints[static_cast<std::size_t>(f.index)] = choiceValue(s, f);
      continue;
    }
    if (it == s.given.end() && f.defaults.empty()) {
      if (f.array == FieldArray::kInts && std::string(f.name) == "threads" && static_cast<std::size_t>(f.index) < nInts) {
        s.spec.ints[static_cast<std::size_t>(f.index)] = -1;  // the server's default
      }
      continue;
    }
    const int line = it != s.given.end() ? it->second.first : s.line;
    const std::string where = s.spec.name + "." + f.name;
    switch (f.array) {
      case FieldArray::kReals: {
        std::vector<double> values = f.defaults;
        if (it != s.given.end()) {
          values.clear();
          for (const std::string& part : words(it->second.second)) values.push_back(parseReal(line, where, part));
        }
        if (f.type == FieldType::kRealList) {  // the last field of its layout: to the end of reals
          for (std::size_t i = 0; i < values.size(); ++i) s.spec.reals[static_cast<std::size_t>(f.index) - 1 + i] = values[i];
          break;
        }
        for (int i = 0; i < f.count; ++i) {
          const std::size_t slot = static_cast<std::size_t>(f.index + i);
          std::string& previous = owner[3 * slot];
          if (it != s.given.end() && !previous.empty() && s.given.contains(previous)) {
            bad(line, where, it->second.second, "takes the place of " + previous + " (give one of them)");
          }
          if (it != s.given.end() || previous.empty()) {
            s.spec.reals[slot - 1] = values[static_cast<std::size_t>(i)];
            previous = f.name;
          }
        }
        break;
      }
      case FieldArray::kInts:
        s.spec.ints[static_cast<std::size_t>(f.index)] = parseInt(line, where, it->second.second);
        break;
      case FieldArray::kStrings:
        if (f.type == FieldType::kTextList) {
          for (const std::string& name : words(it->second.second)) s.spec.strings.push_back(name);
        } else {
          s.spec.strings[static_cast<std::size_t>(f.index - 2)] = it->second.second;
        }
        break;
    }
  }
  if (s.spec.kind == "simulation_box") {
    // The layout reads bounds only from a package of 12 or more reals: both or neither.
    const bool lower = s.given.contains("bounds_lower");
    const bool upper = s.given.contains("bounds_upper");
    if (lower != upper) bad(s.line, s.spec.name + ".bounds_" + (lower ? "upper" : "lower"), "", "missing (give both bounds)");
    if (!lower && nReals > 6) {
      bad(s.line, s.spec.name + ".bounds_lower", "",
          "missing: vtk_interval and the fields after it need bounds_lower and bounds_upper");
    }
  }
}

}  // namespace

FmuConfig parseConfig(std::string_view text) {
  FmuConfig config;
  std::istringstream in{std::string(text)};
  std::string raw;
  int line = 0;
  std::vector<Section> sections;
  const auto finishSection = [&] {
    if (sections.empty()) return;
    Section& s = sections.back();
    buildLayout(s);
    config.components.push_back(s.spec);
  };
  while (std::getline(in, raw)) {
    ++line;
    if (const std::size_t hash = raw.find('#'); hash != std::string::npos) raw.erase(hash);
    const std::string content = trim(raw);
    if (content.empty()) continue;
    if (content.front() == '[') {
      if (content.back() != ']') bad(line, "section", content, "expected [KIND NAME]");
      finishSection();
      const std::vector<std::string> parts = words(content.substr(1, content.size() - 2));
      if (parts.size() != 2) bad(line, "section", content, "expected [KIND NAME]");
      Section s;
      s.line = line;
      s.spec.kind = parts[0];
      s.spec.name = parts[1];
      try {
        (void)isExchanged(s.spec.kind);
      } catch (const std::invalid_argument& e) {
        bad(line, "component kind", s.spec.kind, e.what());
      }
      if (!isIdentifier(s.spec.name)) bad(line, "component name", s.spec.name, "must be an identifier (it names FMI variables)");
      for (const Section& other : sections) {
        if (other.spec.name == s.spec.name) bad(line, "component name", s.spec.name, "declared twice");
      }
      sections.push_back(std::move(s));
      continue;
    }
    if (content.rfind("component ", 0) == 0) {
      bad(line, "component", content.substr(10),
          "the positional form is gone: write [KIND NAME] and one `field = value` per line (docs/fmi.md)");
    }
    const std::size_t eq = content.find('=');
    if (eq == std::string::npos) bad(line, "line", content, "expected `field = value` or [KIND NAME]");
    const std::string key = trim(content.substr(0, eq));
    const std::string value = trim(content.substr(eq + 1));
    if (!sections.empty()) {
      Section& s = sections.back();
      const std::vector<FieldSpec>& fields = fieldsOf(s.spec.kind);
      const auto f = std::find_if(fields.begin(), fields.end(), [&](const FieldSpec& c) { return key == c.name; });
      if (f == fields.end()) {
        if (isStatement(key)) {
          bad(line, key, value, "is a statement of the whole FMU: it goes before the first [KIND NAME]");
        }
        bad(line, s.spec.name + "." + key, value, "unknown field of " + s.spec.kind + " (" + fieldNames(fields) + ")");
      }
      if (s.given.contains(key)) bad(line, s.spec.name + "." + key, value, "given twice");
      checkField(s, *f, line, value);
      s.given[key] = {line, value};
      continue;
    }
    if (key == "model") {
      if (!isIdentifier(value)) bad(line, "model", value, "must be a C identifier (letters, digits, _)");
      config.model_identifier = value;
    } else if (key == "description") {
      config.description = value;
    } else if (key == "host") {
      config.host = value;
    } else if (key == "port") {
      config.port = static_cast<int>(parseInt(line, "port", value));
      if (config.port <= 0 || config.port > 65535) bad(line, "port", value, "must be in 1..65535");
    } else if (key == "token") {
      config.token = value;
    } else if (key == "client_name") {
      config.client_name = value;
    } else if (key == "timeout") {
      config.timeout_s = parseReal(line, "timeout", value);
      if (!(config.timeout_s > 0.0)) bad(line, "timeout", value, "must be > 0");
    } else if (key == "interval") {
      config.interval_s = parseReal(line, "interval", value);
      if (!(config.interval_s > 0.0) || !std::isfinite(config.interval_s)) bad(line, "interval", value, "must be > 0");
    } else if (key == "exchange_order") {
      if (value == "send_first") {
        config.exchange_order = ExchangeOrder::kSendFirst;
      } else if (value == "receive_first") {
        config.exchange_order = ExchangeOrder::kReceiveFirst;
      } else {
        bad(line, "exchange_order", value, "must be send_first or receive_first");
      }
    } else {
      bad(line, key, value,
          std::string("unknown statement (") + kStatements + "); component fields go under a [KIND NAME] line");
    }
  }
  finishSection();
  if (config.model_identifier.empty()) bad(line, "model", "", "missing");
  if (!(config.interval_s > 0.0)) bad(line, "interval", "", "missing");
  if (config.components.empty()) bad(line, "component", "", "no component declared ([KIND NAME])");
  if (config.client_name.empty()) config.client_name = config.model_identifier;
  // A box without expected_count expects exactly this FMU's components.
  for (std::size_t i = 0; i < sections.size(); ++i) {
    ComponentSpec& c = config.components[i];
    if (c.kind == "simulation_box" && !sections[i].given.contains("expected_count") && !c.ints.empty()) {
      c.ints[0] = static_cast<long long>(config.components.size());
    }
  }
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
  add({"host", "Host of demlink-server", VariableType::kString, "", Causality::kParameter, 0, 0.0, config.host,
       Slot::kHost});
  add({"port", "TCP port of demlink-server", VariableType::kInteger, "", Causality::kParameter, 0,
       static_cast<double>(config.port), "", Slot::kPort});
  add({"token", "Access token (empty: none)", VariableType::kString, "", Causality::kParameter, 0, 0.0, config.token,
       Slot::kToken});
  add({"timeout", "Longest wait for the server in one call", VariableType::kReal, "s", Causality::kParameter, 0,
       config.timeout_s, "", Slot::kTimeout});
  const std::string outputTiming = config.exchange_order == ExchangeOrder::kSendFirst
                                       ? " (the interval the last step spanned)"
                                       : " (the interval that ended one step before the last step's end)";
  for (std::size_t ci = 0; ci < config.components.size(); ++ci) {
    const ComponentSpec& c = config.components[ci];
    if (!isExchanged(c.kind)) continue;
    const KindLayout& layout = layoutOf(c.kind);
    const int component = static_cast<int>(ci);
    for (std::size_t i = 0; i < layout.input_reals.size(); ++i) {
      const Signal& in = layout.input_reals[i];
      add({c.name + "." + in.name, in.description + " at the step's start", VariableType::kReal, in.unit,
           Causality::kInput, 0, inputStart(c, static_cast<int>(i)), "", Slot::kInputReal, component,
           static_cast<int>(i)});
    }
    for (std::size_t i = 0; i < layout.output_ints.size(); ++i) {
      const Signal& signal = layout.output_ints[i];
      add({c.name + "." + signal.name, signal.description + outputTiming, VariableType::kInteger, "", Causality::kOutput, 0,
           0.0, "", Slot::kOutputInt, component, static_cast<int>(i)});
    }
    for (std::size_t i = 0; i < layout.output_reals.size(); ++i) {
      const Signal& signal = layout.output_reals[i];
      add({c.name + "." + signal.name, signal.description + outputTiming, VariableType::kReal, signal.unit, Causality::kOutput,
           0, 0.0, "", Slot::kOutputReal, component, static_cast<int>(i)});
    }
  }
  return out;
}

const std::vector<UnitDefinition>& unitDefinitions() {
  static const std::vector<UnitDefinition> units = {
      {"1", 0, 0, 0, 0},     {"s", 0, 0, 1, 0},     {"1/s", 0, 0, -1, 0},  {"m", 0, 1, 0, 0},
      {"m/s", 0, 1, -1, 0},  {"m/s2", 0, 1, -2, 0}, {"rad/s", 0, 0, -1, 1}, {"kg", 1, 0, 0, 0},
      {"N", 1, 1, -2, 0},    {"N.m", 1, 2, -2, 0},  {"J", 1, 2, -2, 0},
  };
  return units;
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
    << "  <UnitDefinitions>\n";
  for (const UnitDefinition& u : unitDefinitions()) {
    x << "    <Unit name=\"" << u.name << "\"><BaseUnit";
    const std::pair<const char*, int> exponents[] = {{"kg", u.kg}, {"m", u.m}, {"s", u.s}, {"rad", u.rad}};
    for (const auto& [base, exponent] : exponents) {
      if (exponent != 0) x << " " << base << "=\"" << exponent << "\"";
    }
    x << "/></Unit>\n";
  }
  x << "  </UnitDefinitions>\n"
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
    if (!v.unit.empty()) x << " unit=\"" << v.unit << "\"";
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
