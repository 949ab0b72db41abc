#pragma once
/// The command line every DEMLink program shares, on CLI11:
/// - `--help` (`-h`) and `--version` print on stdout and exit 0;
/// - a bad command line prints one "error: ..." line on stderr and exits 2; a bad value
///   names the option and the value: "error: <option> = <value>: <reason>";
/// - a value option given twice keeps the last value.
/// The adders below convert the value text themselves (CLI11's own conversions would
/// accept "2.5" for a count by rounding, and word their errors without the value).
#include <CLI/CLI.hpp>

#include <charconv>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>

#include "demlink/cli/version.hpp"

namespace demlink::cli {

/// Refuses `value` of `option`: parse() prints "error: <option> = <value>: <reason>", exit 2.
[[noreturn]] inline void refuse(const std::string& option, const std::string& value, const std::string& reason) {
  throw CLI::ValidationError(option + " = " + value + ": " + reason, CLI::ExitCodes::ValidationError);
}

/// The whole of `text` as an integer in [low, high]; "2.5", "1e20", "1x" are refused.
template <typename Integer>
Integer wholeNumber(const std::string& option, const std::string& text, Integer low, Integer high) {
  Integer value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < low || value > high) {
    refuse(option, text, "not a whole number in " + std::to_string(low) + ".." + std::to_string(high));
  }
  return value;
}

/// The whole of `text` as a finite number; "5s", "nan", "inf" are refused.
inline double number(const std::string& option, const std::string& text) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    refuse(option, text, "not a number");
  }
  return value;
}

/// Adds a value option whose text `store` converts (refusing bad text with refuse()).
inline CLI::Option* addValue(CLI::App& app, const std::string& name, const std::string& help,
                             std::function<void(const std::string&)> store) {
  return app.add_option_function<std::string>(name, std::move(store), help)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

/// A non-empty text; `Target` is std::string or std::optional<std::string>.
template <typename Target>
CLI::Option* addText(CLI::App& app, const std::string& name, Target& target, const std::string& help) {
  return addValue(app, name, help, [&target, name](const std::string& text) {
    if (text.empty()) refuse(name, "\"\"", "must not be empty");
    target = text;
  })->type_name("TEXT");
}

/// A whole number in [low, high].
template <typename Integer>
CLI::Option* addWholeNumber(CLI::App& app, const std::string& name, Integer& target, Integer low, Integer high,
                            const std::string& help) {
  return addValue(app, name, help, [&target, name, low, high](const std::string& text) {
    target = wholeNumber(name, text, low, high);
  })->type_name("N");
}

/// Which numbers addNumber() keeps: at least `low` (above it when `strictly`), below `high`.
struct Range {
  double low = 0.0;
  bool strictly = false;
  double high = std::numeric_limits<double>::infinity();
};

/// A finite number within `range`, refused as "must be >= low" or "must be > low" (and
/// "< high" when bounded); `Target` is double or std::optional<double>.
template <typename Target>
CLI::Option* addNumber(CLI::App& app, const std::string& name, Target& target, Range range, const std::string& help) {
  return addValue(app, name, help, [&target, name, range](const std::string& text) {
    const double value = number(name, text);
    if ((range.strictly ? !(value > range.low) : !(value >= range.low)) || !(value < range.high)) {
      std::ostringstream bound;
      bound << (range.strictly ? "must be > " : "must be >= ") << range.low;
      if (std::isfinite(range.high)) bound << " and < " << range.high;
      refuse(name, text, bound.str());
    }
    target = value;
  })->type_name("X");
}

/// Parses the command line into `app` (adding --version). Returns the exit code when the
/// program should stop now: 0 after --help or --version, 2 after a bad command line;
/// std::nullopt when it should go on.
inline std::optional<int> parse(CLI::App& app, int argc, const char* const* argv) {
  app.set_version_flag("--version", versionLine(app.get_name()), "print the version and git revision, then exit");
  // An option the program does not know is named first: CLI11 would report a missing
  // positional argument before it, which hides the real mistake.
  for (int k = 1; k < argc; ++k) {
    const std::string word = argv[k];
    if (word == "--") break;
    if (word.size() < 2 || word[0] != '-' || (word[1] >= '0' && word[1] <= '9') || word[1] == '.') continue;
    const std::string name = word.substr(0, word.find('='));
    if (app.get_option_no_throw(name) == nullptr) {
      std::cerr << "error: " << name << ": unknown option\n(" << app.get_name() << " --help lists the options)\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return app.exit(error);
    std::cerr << "error: " << error.what() << "\n(" << app.get_name() << " --help lists the options)\n";
    return 2;
  }
  return std::nullopt;
}

}  // namespace demlink::cli
