/// demlink-study: the speed-for-accuracy atlas (docs/accuracy.md).
///
/// Sweeps one knob at a time against the finest setting (time step 0.1 of the critical
/// limit, velocity Verlet, Hertz-Mindlin, skin half the smallest radius, the reference
/// modulus, no coarse graining) and measures, for every setting, the cost (wall seconds per
/// simulated second, particle-steps per second) and bulk quantities (study_scenes.hpp):
/// restitution of a binary impact, packing fraction of a settled bed, drag on a blade pushed
/// through it, angle of repose of a heap, hopper discharge rate. A second sweep couples a
/// plate whose dynamics a client integrates (study_coupling.hpp) at several communication
/// intervals and masses. Errors are relative to the finest run. A bulk quantity of a few
/// hundred grains changes with the initial jitter alone: --seeds K runs every setting with
/// K seeds and reports the mean, its standard error and the noise floor (the spread between
/// the finest setting's seeds); --scale S grows every bed's footprint and grain count by S.
///
/// Writes <out>/atlas.csv (one line per run and metric), <out>/atlas_summary.csv (mean over
/// the seeds, standard errors, whether the error is resolved) and <out>/coupling.csv;
/// scripts/plot_atlas.py draws them.
///   demlink-study [--out DIR] [--jobs J] [--seeds K] [--scale S] [--smoke]
/// J scene workers run beside one thread for the coupling sweep (J = 1 keeps two cores busy).
/// --smoke runs a small subset in seconds and checks the files' structure and that every
/// value is sane (exit code 1 otherwise): the CI test. No timing is checked.
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>

#include "demlink/cli/command_line.hpp"
#include "demlink/core/output/csv_table.hpp"
#include "study_coupling.hpp"
#include "study_scenes.hpp"

namespace {

using namespace demlink::study;
namespace core = demlink::core;

struct Setting {
  std::string knob;   ///< the swept knob ("reference" for the finest run)
  std::string value;  ///< its value as text
  Knobs knobs;
};

std::string text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

/// A number cell of the study's CSVs by the engine's rule (core::csvNumber: NaN, a value
/// that does not exist, is an empty cell). An infinity here is a ratio to a zero
/// reference or time, which does not exist either.
std::string cell(double value) { return core::csvNumber(std::isinf(value) ? std::nan("") : value); }

/// The sweeps; one seed per setting adds a second seed of the finest one as a noise row.
std::vector<Setting> settings(bool smoke, std::uint32_t seeds) {
  std::vector<Setting> out{{"reference", "finest", Knobs{}}};
  auto add = [&](const std::string& knob, const std::string& value, auto change) {
    Knobs k;
    change(k);
    out.push_back({knob, value, k});
  };
  if (smoke) {
    add("dt_fraction", "1", [](Knobs& k) { k.dt_fraction = 1.0; });
    add("modulus_scale", "0.1", [](Knobs& k) { k.modulus_scale = 0.1; });
    add("coarse", "1.5", [](Knobs& k) { k.coarse = 1.5; });
    return out;
  }
  if (seeds == 1) add("seed", "2", [](Knobs& k) { k.seed = 2; });
  for (double f : {0.2, 0.5, 1.0, 1.5, 2.0, 3.0}) add("dt_fraction", text(f), [f](Knobs& k) { k.dt_fraction = f; });
  add("integrator", "explicit_euler", [](Knobs& k) { k.integrator = core::IntegratorKind::ExplicitEuler; });
  add("law", "linear_spring_dashpot", [](Knobs& k) { k.law = core::ContactModel::LinearSpringDashpot; });
  for (double s : {0.25, 1.0, 2.0}) add("skin_factor", text(s), [s](Knobs& k) { k.skin_factor = s; });
  for (double e : {0.1, 0.01, 0.001}) add("modulus_scale", text(e), [e](Knobs& k) { k.modulus_scale = e; });
  for (double a : {1.5, 2.0, 3.0}) add("coarse", text(a), [a](Knobs& k) { k.coarse = a; });
  return out;
}

Budget smokeBudget() {
  Budget b;
  b.bed_grains = 300;
  b.bed_area = 0.3;
  b.heap_grains = 300;
  b.hopper_grains = 200;
  b.bed_settle = 0.15;
  b.drag_time = 0.1;
  // A 300-grain bed's drag moves by a quarter from one trajectory to the next (seeds, or
  // the rounding of one operation); at 4e5 J/m^3 the cohesive drag is twice the dry one on
  // every seed tried (seeds 1-5: 5.0-11.8 N against 1.3-2.6 N), so the check below
  // tests cohesion, not one trajectory.
  b.cohesion_energy_density = 4.0e5;
  b.heap_time = 0.3;
  b.hopper_fill = 0.15;
  b.hopper_flow = 0.08;
  b.cpu_limit = 60.0;
  return b;
}

SceneResult runScene(const std::string& scene, const Knobs& knobs, const Budget& budget, SettledBed settled = {}) {
  try {
    if (scene == "impact") return runImpact(knobs);
    if (scene == "bed") return runBed(knobs, budget, false, settled);
    if (scene == "bed_cohesive") return runBed(knobs, budget, true, settled);
    if (scene == "heap") return runHeap(knobs, budget);
    return runHopper(knobs, budget);
  } catch (const std::exception& error) {
    SceneResult failed(scene);
    failed.status = std::string("broke: ") + error.what();
    return failed;
  }
}

/// CSV field: quoted when it holds a comma or a quote.
std::string field(const std::string& value) {
  if (value.find_first_of(",\"") == std::string::npos) return value;
  std::string quoted = "\"";
  for (char c : value) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

struct Row {
  const Setting* setting;
  Knobs knobs;  ///< the setting's, with this run's seed
  double dt;
  SceneResult result;
  double cpu = 0.0;  ///< CPU seconds of the scene's thread: the cost on a shared machine [s]
};

constexpr const char* kAtlasHeader =
    "knob,value,dt_fraction,dt_s,law,integrator,skin_factor,modulus_scale,coarse,seed,scene,status,"
    "simulated_s,wall_s,cpu_s,wall_per_simulated,particle_steps_per_s,metric,metric_value,reference_value,"
    "relative_error\n";
constexpr const char* kCouplingHeader =
    "interval_steps,interval_s,mass_kg,order,status,depth_m,oscillation_m,reference_depth_m,depth_error_m,"
    "wall_s,simulated_s,particle_steps_per_s\n";

/// The CSV lines of one scene run; `reference` maps "scene/metric" to the finest run's
/// value (empty while the sweep runs: the columns stay NaN).
std::string atlasLines(const Row& row, const std::map<std::string, double>& reference) {
  const Knobs& k = row.knobs;
  const SceneResult& r = row.result;
  const std::string head = field(row.setting->knob) + "," + field(row.setting->value) + "," + cell(k.dt_fraction) +
                           "," + cell(row.dt) + "," + std::string(core::toString(k.law)) + "," +
                           std::string(core::toString(k.integrator)) + "," + cell(k.skin_factor) + "," +
                           cell(k.modulus_scale) + "," + cell(k.coarse) + "," + std::to_string(k.seed) + "," +
                           r.scene + "," + field(r.status) + "," + cell(r.simulated) + "," + cell(r.wall) + "," + cell(row.cpu) + "," +
                           cell(r.simulated > 0 ? r.wall / r.simulated : std::nan("")) + "," +
                           cell(r.wall > 0 ? r.particle_steps / r.wall : std::nan(""));
  if (r.metrics.empty()) return head + ",,,,\n";
  std::string lines;
  for (const auto& [name, value] : r.metrics) {
    const auto it = reference.find(r.scene + "/" + name);
    const double ref = it == reference.end() ? std::nan("") : it->second;
    lines += head + "," + name + "," + cell(value) + "," + cell(ref) + "," + cell((value - ref) / ref) + "\n";
  }
  return lines;
}

/// The final atlas.csv, with every error against the finest run.
void writeAtlas(const std::filesystem::path& path, const std::vector<Row>& rows) {
  std::map<std::string, double> reference;
  for (const Row& row : rows) {
    if (row.setting->knob != "reference" || row.knobs.seed != 1) continue;  // per-run errors: against seed 1
    for (const auto& [name, value] : row.result.metrics) reference[row.result.scene + "/" + name] = value;
  }
  std::ofstream out(path);
  out << kAtlasHeader;
  for (const Row& row : rows) out << atlasLines(row, reference);
}

/// Mean and standard error of the mean of `values` (NaN error for fewer than two).
std::pair<double, double> meanAndError(const std::vector<double>& values) {
  double mean = 0.0;
  for (double v : values) mean += v;
  mean /= static_cast<double>(values.size());
  if (values.size() < 2) return {mean, std::nan("")};
  double squares = 0.0;
  for (double v : values) squares += (v - mean) * (v - mean);
  const auto n = static_cast<double>(values.size());
  return {mean, std::sqrt(squares / (n - 1.0) / n)};
}

constexpr const char* kSummaryHeader =
    "knob,value,scene,metric,seeds,mean,standard_error,reference_mean,reference_standard_error,relative_error,"
    "relative_error_standard_error,noise_floor,resolved,cpu_s_mean\n";

/// The values of one (setting, scene, metric) over the seeds that ran.
struct SeedValues {
  const Setting* setting;
  std::string scene, metric;
  std::vector<double> values, cpu;
};

/// atlas_summary.csv: per setting, scene and metric the mean over the seeds and its standard
/// error (for one seed, the finest setting's scatter); the error against the finest
/// setting's mean is "resolved" when it exceeds twice their combined standard error.
/// noise_floor is the finest setting's seed-to-seed standard deviation relative to its
/// mean. Returns the groups (the smoke check reads them).
std::vector<SeedValues> writeSummary(const std::filesystem::path& path, const std::vector<Row>& rows) {
  std::vector<SeedValues> groups;
  std::map<std::tuple<const Setting*, std::string, std::string>, std::size_t> index;
  for (const Row& row : rows) {
    if (row.result.status != "ok") continue;
    for (const auto& [metric, value] : row.result.metrics) {
      const auto key = std::make_tuple(row.setting, row.result.scene, metric);
      auto [it, added] = index.try_emplace(key, groups.size());
      if (added) groups.push_back({row.setting, row.result.scene, metric, {}, {}});
      groups[it->second].values.push_back(value);
      groups[it->second].cpu.push_back(row.cpu);
    }
  }
  std::map<std::string, const SeedValues*> reference;  // "scene/metric"
  for (const SeedValues& g : groups) {
    if (g.setting->knob == "reference") reference[g.scene + "/" + g.metric] = &g;
  }
  std::ofstream out(path);
  out << kSummaryHeader;
  for (const SeedValues& g : groups) {
    auto [mean, error] = meanAndError(g.values);
    const double cpu = meanAndError(g.cpu).first;
    double refMean = std::nan(""), refError = std::nan(""), noise = std::nan("");
    if (const auto it = reference.find(g.scene + "/" + g.metric); it != reference.end()) {
      std::tie(refMean, refError) = meanAndError(it->second->values);
      const auto refSeeds = static_cast<double>(it->second->values.size());
      noise = refError * std::sqrt(refSeeds) / std::abs(refMean);
      // One seed: its scatter is taken to be the finest setting's.
      if (std::isnan(error)) error = refError * std::sqrt(refSeeds / static_cast<double>(g.values.size()));
    }
    const double combined = std::hypot(error, refError);
    const std::string resolved = std::isfinite(combined) ? (std::abs(mean - refMean) > 2.0 * combined ? "yes" : "no") : "";
    out << field(g.setting->knob) << "," << field(g.setting->value) << "," << g.scene << "," << g.metric << ","
        << g.values.size() << "," << cell(mean) << "," << cell(error) << "," << cell(refMean) << "," << cell(refError)
        << "," << cell((mean - refMean) / refMean) << "," << cell(combined / std::abs(refMean)) << "," << cell(noise)
        << "," << resolved << "," << cell(cpu) << "\n";
  }
  return groups;
}

std::string couplingLine(const CouplingResult& r, double referenceDepth) {
  return std::to_string(r.c.interval_steps) + "," + cell(r.interval) + "," + cell(r.c.mass) + "," +
         toString(r.c.order) + "," + field(r.status) + "," + cell(r.depth) + "," + cell(r.oscillation) + "," +
         cell(referenceDepth) + "," + cell(r.depth - referenceDepth) + "," + cell(r.wall) + "," + cell(r.simulated) +
         "," + cell(r.wall > 0 ? r.particle_steps / r.wall : std::nan("")) + "\n";
}

/// The final coupling.csv, with every depth against the one-step interval's.
void writeCoupling(const std::filesystem::path& path, const std::vector<CouplingResult>& results) {
  std::map<std::pair<double, int>, double> reference;  // (mass, order) -> depth at one step
  for (const CouplingResult& r : results) {
    if (r.c.interval_steps == 1 && r.status == "ok") reference[{r.c.mass, static_cast<int>(r.c.order)}] = r.depth;
  }
  std::ofstream out(path);
  out << kCouplingHeader;
  for (const CouplingResult& r : results) {
    const auto it = reference.find({r.c.mass, static_cast<int>(r.c.order)});
    out << couplingLine(r, it == reference.end() ? std::nan("") : it->second);
  }
}

/// The smoke run's checks: every scene of every setting ran and its values are sane.
int check(const std::vector<Row>& rows, const std::vector<SeedValues>& summary,
          const std::vector<CouplingResult>& coupling) {
  int failures = 0;
  auto require = [&](bool ok, const std::string& what) {
    if (!ok) {
      std::fprintf(stderr, "check failed: %s\n", what.c_str());
      ++failures;
    }
  };
  const std::map<std::string, std::pair<double, double>> sane{
      {"restitution_ratio", {0.8, 1.2}},  {"packing_fraction", {0.3, 0.72}}, {"drag_force", {1e-4, 100.0}},
      {"repose_angle_deg", {1.0, 60.0}},  {"heap_height", {0.005, 0.2}},      {"discharge_rate", {1e-4, 10.0}},
      {"slump_height_ratio", {0.05, 1.05}}};
  for (const Row& row : rows) {
    const std::string name = row.setting->knob + "=" + row.setting->value + " " + row.result.scene;
    require(row.result.status == "ok", name + " ran (" + row.result.status + ")");
    require(row.result.wall > 0.0 && row.result.particle_steps > 0.0, name + " counted its cost");
    for (const auto& [metric, value] : row.result.metrics) {
      const auto [low, high] = sane.at(metric);
      require(std::isfinite(value) && value >= low && value <= high,
              name + " " + metric + " = " + text(value) + " in [" + text(low) + ", " + text(high) + "]");
    }
  }
  // The finest setting's cohesive bed resists the blade more than its dry one (the other
  // settings' drags are the atlas's errors, checked for sanity only).
  std::map<std::string, double> drag;  // scene -> the finest setting's mean drag [N]
  for (const SeedValues& g : summary) {
    if (g.metric == "drag_force" && g.setting->knob == "reference") drag[g.scene] = meanAndError(g.values).first;
  }
  require(drag.contains("bed") && drag.contains("bed_cohesive") && drag["bed_cohesive"] > 1.2 * drag["bed"],
          "cohesive drag " + text(drag["bed_cohesive"]) + " N > 1.2 x dry " + text(drag["bed"]) + " N");
  for (const CouplingResult& r : coupling) {
    const std::string name = "coupling interval " + std::to_string(r.c.interval_steps);
    require(r.status == "ok", name + " ran (" + r.status + ")");
    // The plate rests in the bed: below its surface, by less than its own half side.
    require(std::isfinite(r.depth) && r.depth > -0.002 && r.depth < 0.015, name + " depth " + text(r.depth));
  }
  return failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::string outDir = "out/atlas";
  std::uint32_t jobs = 1;
  bool smoke = false;
  CLI::App app("The speed-for-accuracy atlas: cost and bulk error of each knob against the finest setting.",
               "demlink-study");
  demlink::cli::addText(app, "--out", outDir, "output directory (default out/atlas)")->type_name("DIR");
  demlink::cli::addWholeNumber<std::uint32_t>(app, "--jobs", jobs, 1, 64, "scene workers (default 1); the coupling sweep runs on one more thread");
  app.add_flag("--smoke", smoke, "a small subset in seconds, with sanity checks (the CI test)");
  std::string knobFilter;
  demlink::cli::addText(app, "--knobs", knobFilter,
                        "run only these sweeps, comma-separated (reference, seed, dt_fraction, integrator, law, "
                        "skin_factor, modulus_scale, coarse); default all")
      ->type_name("LIST");
  std::uint32_t seeds = 1;
  demlink::cli::addWholeNumber<std::uint32_t>(app, "--seeds", seeds, 1, 100,
                                              "seeds per setting (default 1: one extra seed of the finest setting)");
  double scale = 1.0;
  app.add_option("--scale", scale, "bed size factor: footprints and grain counts grow by it (default 1)")
      ->check(CLI::Range(1.0, 100.0));
  double cohesion = -1.0;
  app.add_option("--cohesion", cohesion, "k_c of the cohesive bed [J/m^3] (default 1.5e5)")
      ->check(CLI::Range(0.0, 1e9));
  std::string sceneFilter;
  demlink::cli::addText(app, "--scenes", sceneFilter,
                        "run only these scenes, comma-separated (impact, bed, bed_cohesive, heap, hopper); default all")
      ->type_name("LIST");
  bool skipCoupling = false;
  app.add_flag("--skip-coupling", skipCoupling, "leave out the coupled-plate sweep");
  std::vector<std::uint64_t> couplingIntervals;
  app.add_option("--coupling-intervals", couplingIntervals,
                 "the coupling sweep's intervals in engine steps, comma-separated (default 1,10,100,300,1000; "
                 "include 1, the reference)")
      ->delimiter(',')
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100000}));
  if (const std::optional<int> exitCode = demlink::cli::parse(app, argc, argv)) return *exitCode;
  spdlog::set_level(spdlog::level::err);  // the unsafe time steps warn on purpose
  std::filesystem::create_directories(outDir);

  Budget budget = smoke ? smokeBudget() : Budget{};
  budget.scale = scale;
  if (cohesion >= 0.0) budget.cohesion_energy_density = cohesion;
  std::vector<Setting> sweep = settings(smoke, seeds);
  if (!knobFilter.empty()) {
    std::erase_if(sweep, [&](const Setting& setting) {
      return ("," + knobFilter + ",").find("," + setting.knob + ",") == std::string::npos;
    });
  }
  std::vector<std::string> scenes{"impact", "bed", "bed_cohesive", "heap", "hopper"};
  if (!sceneFilter.empty()) {
    std::erase_if(scenes, [&](const std::string& scene) {
      return ("," + sceneFilter + ",").find("," + scene + ",") == std::string::npos;
    });
  }
  std::vector<Row> rows;
  for (std::uint32_t seed = 1; seed <= seeds; ++seed) {
    // A seed's cohesive strokes after all its other scenes: each starts from the bed its
    // dry row settled (SettledBed), which by then has long been claimed by a worker.
    for (const bool cohesive : {false, true}) {
      for (const Setting& s : sweep) {
        Knobs knobs = s.knobs;
        if (seeds > 1) knobs.seed = seed;
        for (const std::string& scene : scenes) {
          // The impact of two spheres has no jitter: one seed measures it.
          if ((scene == "bed_cohesive") == cohesive && (scene != "impact" || seed == 1)) {
            rows.push_back({&s, knobs, 0.0, SceneResult(scene)});
          }
        }
      }
    }
  }
  // Settled dry beds by setting and seed: written by the bed row, read by bed_cohesive
  // (the maps are not changed once the workers start, each promise is set by one worker).
  std::map<std::pair<const Setting*, std::uint64_t>, std::promise<std::string>> settledPromises;
  std::map<std::pair<const Setting*, std::uint64_t>, std::shared_future<std::string>> settledBeds;
  for (const Row& row : rows) {
    if (row.result.scene != "bed") continue;
    const auto key = std::make_pair(row.setting, row.knobs.seed);
    settledBeds[key] = settledPromises[key].get_future().share();
  }
  // Rows go to the files as they finish (errors NaN), so a stopped sweep keeps what it
  // measured; the files are rewritten with the errors at the end.
  std::ofstream partialAtlas(std::filesystem::path(outDir) / "atlas.csv");
  partialAtlas << kAtlasHeader;
  std::ofstream partialCoupling(std::filesystem::path(outDir) / "coupling.csv");
  partialCoupling << kCouplingHeader;
  std::atomic<std::size_t> next{0};
  std::mutex printing;
  const auto start = std::chrono::steady_clock::now();
  auto worker = [&] {
    for (std::size_t i = next++; i < rows.size(); i = next++) {
      Row& row = rows[i];
      row.dt = row.knobs.dt_fraction * criticalLimit(row.knobs);
      const auto key = std::make_pair(row.setting, row.knobs.seed);
      std::string settled;
      SettledBed share;
      if (row.result.scene == "bed") {
        share.to = &settled;
      } else if (row.result.scene == "bed_cohesive" && settledBeds.contains(key)) {
        settled = settledBeds.at(key).get();  // empty when the dry bed broke: settle here
        if (!settled.empty()) share.from = &settled;
      }
      const double cpuStart = threadCpuSeconds();
      row.result = runScene(row.result.scene, row.knobs, budget, share);
      row.cpu = threadCpuSeconds() - cpuStart;
      if (row.result.scene == "bed") settledPromises.at(key).set_value(std::move(settled));
      const std::lock_guard lock(printing);
      partialAtlas << atlasLines(row, {}) << std::flush;
      std::printf("%-14s %-22s seed %-3llu %-12s %-40.40s wall %7.1f s", row.setting->knob.c_str(),
                  row.setting->value.c_str(), static_cast<unsigned long long>(row.knobs.seed), row.result.scene.c_str(), row.result.status.c_str(), row.result.wall);
      for (const auto& [name, value] : row.result.metrics) std::printf("  %s %.4g", name.c_str(), value);
      std::printf("\n");
      std::fflush(stdout);
    }
  };
  std::vector<std::thread> threads;
  for (std::uint32_t j = 0; j < jobs; ++j) threads.emplace_back(worker);

  // The coupling sweep runs beside the scenes on the calling thread.
  std::vector<CouplingCase> cases;
  const std::vector<std::uint64_t> intervals =
      !couplingIntervals.empty() ? couplingIntervals
      : smoke                    ? std::vector<std::uint64_t>{1, 10}
                                 : std::vector<std::uint64_t>{1, 10, 100, 300, 1000};
  const std::vector<double> masses = smoke ? std::vector<double>{0.2} : std::vector<double>{0.02, 0.2, 2.0};
  for (ClientOrder order : {ClientOrder::SendFirst, ClientOrder::ReceiveFirst}) {
    if (skipCoupling) break;
    if (smoke && order == ClientOrder::ReceiveFirst) continue;
    for (double m : masses) {
      for (std::uint64_t n : intervals) cases.push_back({n, m, order});
    }
  }
  Knobs couplingKnobs;
  couplingKnobs.dt_fraction = 0.5;
  const std::vector<CouplingResult> coupling =
      cases.empty() ? std::vector<CouplingResult>{} : runCoupling(couplingKnobs, smoke ? 150 : 500, smoke ? 0.15 : 0.25, smoke ? 0.05 : 0.2, cases, budget.cpu_limit,
                  [&](const CouplingResult& r) { partialCoupling << couplingLine(r, std::nan("")) << std::flush; });
  for (std::thread& t : threads) t.join();
  partialAtlas.close();
  partialCoupling.close();
  for (const CouplingResult& r : coupling) {
    std::printf("coupling %-18s m %5.3g kg interval %4llu steps (%.3g s): %s depth %.3g mm osc %.3g mm wall %.1f s\n",
                toString(r.c.order), r.c.mass, static_cast<unsigned long long>(r.c.interval_steps), r.interval,
                r.status.c_str(), 1e3 * r.depth, 1e3 * r.oscillation, r.wall);
  }
  writeAtlas(std::filesystem::path(outDir) / "atlas.csv", rows);
  const std::vector<SeedValues> summary = writeSummary(std::filesystem::path(outDir) / "atlas_summary.csv", rows);
  writeCoupling(std::filesystem::path(outDir) / "coupling.csv", coupling);
  std::printf("wall %.1f s -> %s/atlas.csv, atlas_summary.csv, coupling.csv\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), outDir.c_str());
  return smoke ? check(rows, summary, coupling) : 0;
}
