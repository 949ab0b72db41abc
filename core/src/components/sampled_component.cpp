/// Sample schedule and CSV output shared by sensors, sinks and trackers (contract in
/// sampled_component.hpp).
///
/// The period is an integer number of steps so that samples land on exact steps and no
/// floating-point accumulation of time decides whether a sample is taken.
#include "demlink/core/components/sampled_component.hpp"

#include <cmath>
#include <set>

#include "demlink/core/components/component_state.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/step/interval_steps.hpp"
#include "demlink/core/components/component_world.hpp"
#include "demlink/core/step/watchdog.hpp"

namespace demlink::core {

SampledComponent::SampledComponent(std::string name, SampleSchedule schedule, std::string fieldPrefix)
    : WorldComponent(std::move(name)), schedule_(schedule), field_prefix_(std::move(fieldPrefix)) {
  if (schedule_.every_steps == 0) requirePositive(field_prefix_ + ".sample_interval", schedule_.interval);
}

void SampledComponent::resolveSchedule(const ComponentWorld& world) {
  if (schedule_.every_steps > 0) {
    every_ = schedule_.every_steps;
    return;
  }
  IntervalRule rule;
  rule.zero = ZeroInterval::Refused;
  IntervalSteps steps =
      intervalSteps(field_prefix_ + ".sample_interval", schedule_.interval, world.settings().time_step, rule);
  every_ = steps.steps;
  schedule_warning_ = std::move(steps.warning);
}

bool SampledComponent::sampleDue(const ComponentWorld& world) const {
  return every_ > 0 && world.stepCount() % every_ == 0;
}

void SampledComponent::publish(const ComponentWorld& world, std::vector<double> row) {
  // NaN is a missing value (an empty cell); an infinity can only come from a state that is
  // no longer finite, which stops the run as the watchdog would, before anything is recorded.
  for (std::size_t k = 0; k < row.size(); ++k) {
    if (!std::isinf(row[k])) continue;
    const std::vector<std::string> names = columns();
    throw SimulationFault("non_finite_output",
                          std::string(kind()) + " " + name() + " column " + (k < names.size() ? names[k] : "?") +
                              " is " + (row[k] > 0.0 ? "+" : "-") + "inf; the sample is not written",
                          world.stepCount());
  }
  latest_ = std::move(row);
  ++samples_;
  if (csv_) csv_->writeRow(latest_);
}

void SampledComponent::saveState(StateWriter& out) const {
  const std::size_t section = out.beginSection("SMPL");
  out.write(every_);
  out.write(samples_);
  writeWithMissing(out, latest_);
  out.endSection(section);
}

void SampledComponent::loadState(StateReader& in) {
  StateReader s = componentSection(in, "SMPL", "schedule");
  const auto every = s.read<std::uint64_t>();
  if (every != every_) {
    s.fail(std::to_string(every), "sample period in steps differs from the scene's " + std::to_string(every_) +
                                      " (restore into a world built from the same scene)");
  }
  const auto samples = s.read<std::uint64_t>();
  std::vector<double> latest = readWithMissing(s, "latest sample");
  s.requireEnd();
  const std::size_t width = columns().size();
  if (latest.size() != width) {
    s.fail(std::to_string(latest.size()), "latest sample has the wrong number of values (expected " +
                                              std::to_string(width) + ")");
  }
  if (samples == 0) s.fail("0", "sample count must be >= 1 (the initial sample)");
  samples_ = samples;
  latest_ = std::move(latest);
}

void SampledComponent::writeCsvTo(const std::filesystem::path& path) {
  csv_ = std::make_unique<CsvTable>(path, columns());
  if (!latest_.empty()) csv_->writeRow(latest_);
}

std::vector<std::string> sampleScheduleWarnings(const std::vector<std::unique_ptr<WorldComponent>>& components) {
  std::vector<std::string> warnings;
  for (const auto& component : components) {
    const auto* sampled = dynamic_cast<const SampledComponent*>(component.get());
    if (sampled != nullptr && !sampled->scheduleWarning().empty()) warnings.push_back(sampled->scheduleWarning());
  }
  return warnings;
}

std::vector<std::filesystem::path> writeSamplesToCsv(const std::vector<std::unique_ptr<WorldComponent>>& components,
                                                     const std::filesystem::path& directory) {
  std::vector<std::filesystem::path> paths;
  std::set<std::string> used;
  for (const auto& component : components) {
    auto* sampled = dynamic_cast<SampledComponent*>(component.get());
    if (sampled == nullptr) continue;
    std::string stem = std::string(sampled->kind()) + "_" + sampled->name();
    for (char& c : stem) {
      const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                         c == '_' || c == '.';
      if (!plain) c = '_';
    }
    std::string file = stem + ".csv";
    for (int k = 2; !used.insert(file).second; ++k) file = stem + "_" + std::to_string(k) + ".csv";
    paths.push_back(directory / file);
    sampled->writeCsvTo(paths.back());
  }
  return paths;
}

}  // namespace demlink::core
