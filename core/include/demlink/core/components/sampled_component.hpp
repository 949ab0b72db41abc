#pragma once
/// Base of the components that report readings at a fixed sample interval (sinks,
/// region and flow sensors, trackers): the schedule (seconds converted to whole steps),
/// the latest sample as a numeric row, and an optional CSV file that gets every sample.
///
/// Why rows of numbers in the base: the headless runner writes them to CSV and the
/// co-simulation server will forward them to clients; neither needs to know the kind.
/// Typed readings (count, mass, ...) are on each subclass for code that does.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "demlink/core/output/csv_table.hpp"
#include "demlink/core/components/world_component.hpp"

namespace demlink::core {

/// When a component samples: every `every_steps` steps, or (when that is 0) every
/// `interval` seconds of simulated time, converted to whole steps by intervalSteps()
/// (step/interval_steps.hpp: rounded with a warning when off the step grid).
struct SampleSchedule {
  double interval = 0.0;          ///< [s]
  std::uint64_t every_steps = 0;  ///< [-]
};

class SampledComponent : public WorldComponent {
 public:
  /// Throws InputError naming fieldPrefix + ".sample_interval" when every_steps is 0 and
  /// the interval is not finite and > 0.
  SampledComponent(std::string name, SampleSchedule schedule, std::string fieldPrefix);

  /// Column names with units; the first is "time_s".
  [[nodiscard]] virtual std::vector<std::string> columns() const = 0;

  /// Steps between samples [-] (0 before initialize()).
  [[nodiscard]] std::uint64_t sampleEvery() const { return every_; }
  /// The last sample, laid out as columns() (time first); empty before the first sample.
  /// initialize() takes a sample of the initial state.
  [[nodiscard]] const std::vector<double>& latestRow() const { return latest_; }
  /// Number of samples taken so far (including the initial one) [-].
  [[nodiscard]] std::uint64_t sampleCount() const { return samples_; }

  /// Writes every later sample to a CSV file at `path`: the header, the latest sample
  /// (if any) and then each new one, flushed as written. Throws std::runtime_error if
  /// the file cannot be written.
  void writeCsvTo(const std::filesystem::path& path);
  /// The CSV file, or null when none was opened.
  [[nodiscard]] const CsvTable* csv() const { return csv_.get(); }
  /// The warning of the seconds -> steps conversion (the interval was rounded); empty if none.
  [[nodiscard]] const std::string& scheduleWarning() const { return schedule_warning_; }
  /// Scene path of the component's declaration, for error messages.
  [[nodiscard]] const std::string& fieldPrefix() const { return field_prefix_; }

  /// Checkpoint state of the schedule: a "SMPL" section with the sample period (checked
  /// against the scene's on load), the sample count and the latest row (whose length
  /// must match columns()). Subclasses call these first, then add their own section.
  void saveState(StateWriter& out) const override;
  void loadState(StateReader& in) override;

 protected:
  /// Converts the schedule to steps with the world's time step (intervalSteps, 0 refused).
  /// Throws InputError naming fieldPrefix + ".sample_interval" when the interval is shorter
  /// than half a step or spans too many steps.
  void resolveSchedule(const ComponentWorld& world);
  /// True when the world's step count is a multiple of the sample period.
  [[nodiscard]] bool sampleDue(const ComponentWorld& world) const;
  /// Records a sample (row laid out as columns(); NaN for a value that does not exist)
  /// and writes it to the CSV file. Throws SimulationFault "non_finite_output" naming
  /// the column for an infinite value; nothing is recorded then.
  void publish(const ComponentWorld& world, std::vector<double> row);

 private:
  SampleSchedule schedule_;
  std::string field_prefix_;
  std::uint64_t every_ = 0;
  std::string schedule_warning_;
  std::uint64_t samples_ = 0;
  std::vector<double> latest_;
  std::unique_ptr<CsvTable> csv_;
};

/// The scheduleWarning() of every sampled component among `components` that has one.
[[nodiscard]] std::vector<std::string> sampleScheduleWarnings(
    const std::vector<std::unique_ptr<WorldComponent>>& components);

/// Opens a CSV file "<kind>_<name>.csv" in `directory` for every sampled component among
/// `components` (World::components(); characters other than letters, digits, '-', '_' and '.' in the name become
/// '_'); returns the paths. Throws std::runtime_error if a file cannot be written.
std::vector<std::filesystem::path> writeSamplesToCsv(const std::vector<std::unique_ptr<WorldComponent>>& components,
                                                     const std::filesystem::path& directory);

}  // namespace demlink::core
