/// demlink-calibrate: fits sliding friction, rolling friction and/or cohesion of a material
/// so that the atlas's scenes reproduce what the user measured (angle of repose, bulk
/// density, hopper discharge), and writes the result as a materials-file entry a scene
/// loads with simulation_box.materials_file (docs/materials.md "Calibrating a material").
///
///   demlink-calibrate TARGETS [--out FILE] [--dt-fraction X]
///   demlink-calibrate TARGETS --synthetic sliding_friction=0.5[,rolling_friction=0.1] --check
///
/// --synthetic replaces every measured value by the engine's own at those parameters (the
/// mean over seeds no fit uses), so the fit must recover known values: --check exits 1
/// unless each is recovered within max(2 sigma, --tolerance x its bounds' width) with 2 sigma
/// under half the bounds' width.
/// Exit codes (server/src/apps/command_line_main.hpp): 0 done, 1 a scene broke or --check
/// failed, 2 bad input (command line or TARGETS, naming the field and the value), 3 the
/// watchdog stopped a scene.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "calibration_entry.hpp"
#include "calibration_fit.hpp"
#include "calibration_scenes.hpp"
#include "calibration_targets.hpp"
#include "command_line_main.hpp"
#include "demlink/cli/command_line.hpp"
#include "demlink/core/base/input_error.hpp"

namespace {

using namespace demlink::calibrate;
namespace core = demlink::core;

/// Seeds of the synthetic "measurements": none of the fit's or the scatter's (1..20).
constexpr std::uint64_t kSyntheticSeedBase = 1000;

struct CommandLine {
  std::string targets;
  std::string out;
  double dt_fraction = 0.5;
  std::string synthetic;
  bool check = false;
  double tolerance = 0.05;
};

std::string text(double value, int digits = 4) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  return buffer;
}

double processCpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

/// "name=value,name=value" for the fitted parameters, in the order of `fit`.
std::vector<double> syntheticValues(const std::string& spec, const std::vector<FitParameter>& fit) {
  std::map<std::string, double> given;
  std::stringstream items(spec);
  std::string item;
  while (std::getline(items, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw core::InputError("--synthetic", item, "expected name=value");
    given[item.substr(0, eq)] = demlink::cli::number("--synthetic", item.substr(eq + 1));
  }
  std::vector<double> values;
  for (const FitParameter& p : fit) {
    const auto it = given.find(parameterName(p.parameter));
    if (it == given.end()) {
      throw core::InputError("--synthetic", spec, std::string("gives no value for the fitted ") + parameterName(p.parameter));
    }
    if (it->second < p.bounds.min || it->second > p.bounds.max) {
      throw core::InputError("--synthetic", spec, std::string(parameterName(p.parameter)) + " lies outside its bounds");
    }
    values.push_back(it->second);
    given.erase(it);
  }
  if (!given.empty()) throw core::InputError("--synthetic", given.begin()->first, "is not a fitted parameter");
  return values;
}

/// Mean and sample standard deviation.
std::pair<double, double> meanAndScatter(const std::vector<double>& values) {
  double mean = 0.0;
  for (double v : values) mean += v;
  mean /= static_cast<double>(values.size());
  double squares = 0.0;
  for (double v : values) squares += (v - mean) * (v - mean);
  return {mean, values.size() > 1 ? std::sqrt(squares / static_cast<double>(values.size() - 1)) : 0.0};
}

/// Runs every measurement's scene for `material` over `seeds` seeds from `firstSeed`;
/// returns [measurement][seed].
std::vector<std::vector<double>> measureAll(const Targets& targets, const core::Material& material,
                                            std::uint64_t firstSeed, std::uint32_t seeds, double dtFraction) {
  const demlink::study::Grains grains = grainsOf(material, targets.base.size);
  std::vector<std::vector<double>> out;
  for (const Measurement& m : targets.measurements) {
    std::vector<double> values;
    for (std::uint32_t s = 0; s < seeds; ++s) values.push_back(measure(m, grains, firstSeed + s, dtFraction));
    out.push_back(std::move(values));
  }
  return out;
}

/// The material the scenes run with `values` of the fitted parameters.
core::Material withParameters(const Targets& targets, const std::vector<double>& values) {
  return calibratedRecord(targets, values).material;
}

std::string parameterList(const Targets& targets, const std::vector<double>& values) {
  std::string out;
  for (std::size_t j = 0; j < values.size(); ++j) {
    out += (j > 0 ? ", " : "") + std::string(parameterName(targets.fit[j].parameter)) + " " + text(values[j]);
  }
  return out;
}

int run(int argc, char** argv) {
  CommandLine line;
  CLI::App app("Fits sliding friction, rolling friction and/or cohesion of a material to measured bulk quantities "
               "(docs/materials.md \"Calibrating a material\").",
               "demlink-calibrate");
  app.add_option("TARGETS", line.targets, "the targets file (JSON, proto/demlink/v1/calibration.proto)")->required();
  demlink::cli::addText(app, "--out", line.out, "materials file to write (default: <name>.csv)");
  demlink::cli::addValue(app, "--dt-fraction",
                         "time step / critical limit of every scene, in (0, 1] (default 0.5: the ENGINEERING preset)",
                         [&line](const std::string& value) {
                           line.dt_fraction = demlink::cli::number("--dt-fraction", value);
                           if (!(line.dt_fraction > 0.0 && line.dt_fraction <= 1.0)) {
                             demlink::cli::refuse("--dt-fraction", value,
                                                  "must be in (0, 1]: 1 is the largest step a scene accepts");
                           }
                         })
      ->type_name("X");
  demlink::cli::addText(app, "--synthetic", line.synthetic,
                        "replace the measured values by the engine's own at these parameters (name=value,...)");
  app.add_flag("--check", line.check, "with --synthetic: exit 1 unless every parameter is recovered (within max(2 sigma, tolerance), 2 sigma below half the bounds)");
  demlink::cli::addNumber(app, "--tolerance", line.tolerance, {0.0, false},
                          "with --check: accepted error as a share of the bounds' width when above 2 sigma (default 0.05)");
  if (const std::optional<int> exitCode = demlink::cli::parse(app, argc, argv)) return *exitCode;
  if (line.check && line.synthetic.empty()) throw core::InputError("--check", "", "needs --synthetic");
  spdlog::set_level(spdlog::level::warn);  // the engine's warnings only, not its set-up log

  const auto wallStart = std::chrono::steady_clock::now();
  const double cpuStart = processCpuSeconds();
  Targets targets = readTargets(line.targets);
  const std::string outFile = line.out.empty() ? targets.name + ".csv" : line.out;

  std::optional<std::vector<double>> truth;
  if (!line.synthetic.empty()) {
    truth = syntheticValues(line.synthetic, targets.fit);
    std::fprintf(stderr, "synthetic measurements at %s (seeds %llu..%llu)\n", parameterList(targets, *truth).c_str(),
                 static_cast<unsigned long long>(kSyntheticSeedBase + 1),
                 static_cast<unsigned long long>(kSyntheticSeedBase + targets.uncertainty_seeds));
    const auto values = measureAll(targets, withParameters(targets, *truth), kSyntheticSeedBase + 1,
                                   targets.uncertainty_seeds, line.dt_fraction);
    for (std::size_t m = 0; m < values.size(); ++m) targets.measurements[m].value = meanAndScatter(values[m]).first;
  }

  std::vector<Bounds> bounds;
  for (const FitParameter& p : targets.fit) bounds.push_back(p.bounds);
  std::vector<double> goal;
  for (const Measurement& m : targets.measurements) goal.push_back(m.value);

  std::size_t index = 0, planned = 0;
  FitOptions options;
  options.progress = [&](std::size_t i, std::size_t n, const std::vector<double>&) {
    index = i;
    planned = n;
  };
  const Evaluate evaluate = [&](const std::vector<double>& p) {
    const auto start = std::chrono::steady_clock::now();
    const auto values = measureAll(targets, withParameters(targets, p), 1, targets.fit_seeds, line.dt_fraction);
    std::vector<double> means;
    std::string shown;
    for (std::size_t m = 0; m < values.size(); ++m) {
      means.push_back(meanAndScatter(values[m]).first);
      shown += std::string(", ") + quantityName(targets.measurements[m].quantity) + " " + text(means.back()) + " " +
               quantityUnit(targets.measurements[m].quantity);
    }
    std::fprintf(stderr, "[%zu/%zu] %s%s (%u seeds, %.1f s)\n", index + 1, planned, parameterList(targets, p).c_str(),
                 shown.c_str(), targets.fit_seeds,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return means;
  };
  const FitResult fit = fitParameters(bounds, goal, evaluate, options);

  std::fprintf(stderr, "scatter: %u seeds at %s\n", targets.uncertainty_seeds,
               parameterList(targets, fit.parameters).c_str());
  const auto atFit = measureAll(targets, withParameters(targets, fit.parameters), 1, targets.uncertainty_seeds, line.dt_fraction);
  std::vector<double> means, scatter;
  for (const auto& values : atFit) {
    const auto [mean, sd] = meanAndScatter(values);
    means.push_back(mean);
    scatter.push_back(sd);
  }
  const std::vector<double> sigma = parameterUncertainty(fit.slopes, scatter);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
  const double cpu = processCpuSeconds() - cpuStart;

  std::ostringstream report;
  report << "calibration of " << targets.base.material.name << " (" << line.targets << "): " << fit.evaluations.size()
         << " evaluations x " << targets.fit_seeds << " seeds, then " << targets.uncertainty_seeds
         << " seeds at the fit; time step " << text(line.dt_fraction) << " of the critical limit\n\n";
  report << "| parameter | bounds | fitted | uncertainty (1 sigma) |" << (truth ? " true | error / sigma |" : "") << "\n";
  report << "|---|---|---|---|" << (truth ? "---|---|" : "") << "\n";
  bool recovered = true;
  for (std::size_t j = 0; j < targets.fit.size(); ++j) {
    const Bounds& b = targets.fit[j].bounds;
    report << "| " << parameterName(targets.fit[j].parameter) << " | " << text(b.min) << " - " << text(b.max) << " | "
           << text(fit.parameters[j]) << (fit.at_bound[j] ? " (at a bound: widen it)" : "") << " | "
           << (std::isnan(sigma[j]) ? std::string("not determined") : text(sigma[j], 2)) << " |";
    if (truth) {
      const double error = fit.parameters[j] - (*truth)[j];
      // A parameter the scenes hardly see has a large sigma that would excuse any error:
      // recovered means within max(2 sigma, tolerance) with 2 sigma under half the bounds.
      const double allowed = std::max(2.0 * sigma[j], line.tolerance * (b.max - b.min));
      const bool determined = 2.0 * sigma[j] <= 0.5 * (b.max - b.min);
      const bool ok = determined && std::abs(error) <= allowed;
      recovered = recovered && ok;
      report << " " << text((*truth)[j]) << " | " << text(error / sigma[j], 2)
             << (ok ? "" : determined ? " NOT RECOVERED" : " NOT DETERMINED (2 sigma > half the bounds)") << " |";
    }
    report << "\n";
  }
  report << "\n| measurement | unit | target | at the fit (mean) | scatter (SD of one seed) | relative misfit |";
  for (const FitParameter& p : targets.fit) report << " slope per " << parameterName(p.parameter) << " |";
  report << "\n|---|---|---|---|---|---|";
  for (std::size_t j = 0; j < targets.fit.size(); ++j) report << "---|";
  report << "\n";
  for (std::size_t m = 0; m < targets.measurements.size(); ++m) {
    const Measurement& measurement = targets.measurements[m];
    report << "| " << quantityName(measurement.quantity)
           << (measurement.quantity == Quantity::HopperDischarge ? " (orifice " + text(measurement.orifice) + " m)" : "")
           << " | " << quantityUnit(measurement.quantity) << " | " << text(measurement.value) << " | "
           << text(means[m]) << " | " << text(scatter[m], 2) << " | "
           << text(100.0 * (means[m] - measurement.value) / measurement.value, 2) << " % |";
    for (double s : fit.slopes[m]) report << " " << text(s, 3) << " |";
    report << "\n";
  }
  report << "\nobjective (sum of squared relative misfits) at the fit: " << text(relativeMisfit(means, goal), 3)
         << "\nrun time: " << text(wall, 3) << " s wall, " << text(cpu, 3) << " s CPU\n";

  writeMaterialsFile(outFile, calibratedRecord(targets, fit.parameters), report.str());
  report << "written: " << outFile << " (entry \"" << targets.name << "\"; load it with simulation_box.materials_file)\n";
  std::cout << report.str();
  if (line.check && !recovered) {
    std::cerr << "error: a parameter was not recovered within max(2 sigma, " << line.tolerance
              << " x its bounds' width), or 2 sigma exceeds half its bounds\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return demlink::server::runCommandLine(run, argc, argv); }
