/// run_log.csv writer (contract in run_log.hpp; columns in docs/state.md).
#include "demlink/server/run/run_log.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "demlink/core/output/csv_table.hpp"

namespace demlink::server {
namespace {

/// RFC 4180 quoting: a field with a comma, quote or line break is enclosed in
/// quotes, inner quotes doubled.
std::string csvField(std::string_view text) {
  if (text.find_first_of(",\"\n\r") == std::string_view::npos) return std::string(text);
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

/// A value cell: the one CSV number rule (core::csvNumber: NaN is an empty cell).
std::string number(double value) { return core::csvNumber(value); }

/// A time step limit: +inf means nothing limits the step (a scene without particles, an
/// unconditionally stable integrator), a value that does not exist: an empty cell.
std::string limit(double seconds) { return number(std::isinf(seconds) ? std::nan("") : seconds); }

}  // namespace

RunLog::RunLog(const std::filesystem::path& path) : out_(path, std::ios::trunc), path_(path) {
  if (!out_) throw std::runtime_error("cannot write " + path.string());
  out_ << "section,key,value,unit\n";
  out_.flush();
}

void RunLog::add(std::string_view section, std::string_view key, std::string_view value, std::string_view unit) {
  out_ << csvField(section) << ',' << csvField(key) << ',' << csvField(value) << ',' << csvField(unit) << '\n';
  out_.flush();
  if (!out_) throw std::runtime_error("cannot write " + path_.string());
}

void RunLog::writeConfiguration(const core::World& world, const RunOptions& run, std::uint64_t endStep) {
  const core::SimulationSettings& s = world.settings();
  const core::TimeStepReport& report = world.timeStepReport();
  add("config", "status", "running");
  add("config", "scene_file", run.scene_file);
  add("config", "restored_from", run.restore_file);
  add("config", "start_time", number(world.time()), "s");
  add("config", "end_time", number(static_cast<double>(endStep) * s.time_step), "s");
  add("config", "time_step", number(s.time_step), "s");
  add("config", "critical_time_step", limit(report.limit), "s");
  add("config", "critical_time_step_limited_by", report.limited_by);
  add("config", "time_step_fraction_of_critical", number(s.time_step / report.limit));
  for (const core::TimeStepConstraint& c : report.constraints) {
    add("time_step_limit", c.name, limit(c.limit), "s");
  }
  add("time_step_limit", "restitution_tolerance", number(report.restitution_tolerance));
  add("time_step_limit", "validated_impact_speed", number(report.impact_speed), "m/s");
  for (const core::PairDampingReport& d : report.damping) {
    const std::string pair = d.material_a + "/" + d.material_b;
    add("damping", pair + " restitution", number(d.restitution));
    add("damping", pair + " c", number(d.damping_coefficient));
    add("damping", pair + " beta", number(d.beta));
    add("damping", pair + " normal_damping", number(d.normal_damping));
    add("damping", pair + " tangential_damping", number(d.tangential_damping));
    add("damping", pair + " step_fraction_of_contact", number(d.step_fraction));
  }
  add("config", "contact_model", core::toString(s.contact_model));
  add("config", "integrator", core::toString(s.integrator));
  add("config", "threads", std::to_string(s.threads));
  if (!s.threads_choice.empty()) add("config", "threads_choice", s.threads_choice);
  add("config", "pair_kernel", std::string(core::pairKernelName(world.pairKernel())));
  add("config", "neighbour_skin", number(world.neighbourSkin()), "m");
  add("config", "sort_every_builds", std::to_string(s.sort_every_builds));
  add("config", "max_impact_velocity", number(s.max_impact_velocity), "m/s");
  add("config", "gravity", fmt::format("{} {} {}", s.gravity.x(), s.gravity.y(), s.gravity.z()), "m/s^2");
  add("config", "particles", std::to_string(world.particles().size()));
  add("config", "materials", std::to_string(world.materials().size()));
  add("config", "planes", std::to_string(world.planes().size()));
  add("config", "meshes", std::to_string(world.meshes().size()));
  std::string stages;
  for (const std::string& stage : world.activeStages()) stages += (stages.empty() ? "" : ";") + stage;
  add("config", "active_stages", stages);
  for (const auto& body : world.deformableBodies()) {
    const std::string& name = body->name();
    add("deformable", name + ".kind", body->kind());
    add("deformable", name + ".nodes", std::to_string(body->nodeCount()));
    add("deformable", name + ".surface_triangles", std::to_string(body->surface().triangles().size()));
    add("deformable", name + ".mass", number(body->totalMass()), "kg");
    add("deformable", name + ".critical_time_step", limit(body->criticalTimeStep()), "s");
    add("deformable", name + ".critical_time_step_set_by", body->criticalTimeStepReason());
  }
  add("config", "output_directory", run.output_directory);
  add("config", "vtk_interval", number(run.vtk_interval), "s");
  add("config", "checkpoint_interval", number(run.checkpoint_interval), "s");
  // Rows of optional outputs only when asked for, so other run logs keep their rows.
  if (run.contact_interval > 0.0) add("config", "contact_interval", number(run.contact_interval), "s");
  if (run.mesh_loads) add("config", "mesh_loads", "true");
}

std::string stageTimingSummary(const core::World& world) {
  const auto seconds = world.stageSeconds();
  double staged = 0.0;
  for (const double s : seconds) staged += s;
  std::string out;
  for (std::size_t k = 0; k < seconds.size(); ++k) {
    if (seconds[k] <= 0.0) continue;
    out += fmt::format("{}{} {:.3g} s ({:.1f} %)", out.empty() ? "" : ", ", core::stageTable()[k].name, seconds[k],
                       100.0 * seconds[k] / std::max(staged, 1e-12));
  }
  return out;
}

void RunLog::writeTiming(const core::World& world, const RunTiming& timing) {
  const double total = std::max(timing.total_seconds, 1.0e-9);
  const double stepping = std::max(total - timing.output_seconds, 1.0e-9);
  add("timing", "initialise_wall", number(timing.initialise_seconds), "s");
  add("timing", "total_wall", number(timing.total_seconds), "s");
  // Per stage (World::setStageTiming, sampled): seconds and share of the stepping time.
  const auto stageSeconds = world.stageSeconds();
  for (std::size_t k = 0; k < stageSeconds.size(); ++k) {
    if (stageSeconds[k] <= 0.0) continue;
    const std::string name(core::stageTable()[k].name);
    add("stage_timing", name, number(stageSeconds[k]), "s");
    add("stage_timing", name + " share", number(stageSeconds[k] / stepping));
  }
  add("timing", "stepping_wall", number(total - timing.output_seconds), "s");
  add("timing", "output_wall", number(timing.output_seconds), "s");
  add("timing", "steps", std::to_string(timing.steps));
  add("timing", "steps_per_second", number(static_cast<double>(timing.steps) / stepping), "1/s");
  add("timing", "particle_steps_per_second", number(static_cast<double>(timing.particle_steps) / stepping), "1/s");
  add("timing", "neighbour_builds", std::to_string(timing.neighbour_builds));
  add("timing", "frames", std::to_string(timing.frames));
  add("timing", "checkpoints", std::to_string(timing.checkpoints));
  add("timing", "final_time", number(world.time()), "s");
  add("timing", "final_particles", std::to_string(world.particles().size()));
  add("timing", "final_kinetic_energy", number(world.kineticEnergy()), "J");
  add("timing", "removed_at_bounds", std::to_string(world.removedAtBounds().count));
  add("timing", "removed_mass_at_bounds", number(world.removedAtBounds().mass), "kg");
  for (const auto& body : world.deformableBodies()) {
    add("deformable", body->name() + ".broken_springs", std::to_string(body->brokenCount()));
    add("deformable", body->name() + ".final_kinetic_energy", number(body->kineticEnergy()), "J");
  }
  add("timing", "status", "completed");
}

}  // namespace demlink::server
