/// The LIGGGHTS backend (contract in liggghts_backend.hpp).
///
/// LIGGGHTS reports its own input errors by printing and exiting the process (its Error
/// class calls exit after MPI_Finalize); that is why every check that can be made on our
/// side (requireLiggghtsCompatible, the time-step check, lost particles) is made before
/// a command reaches it. Its messages go to liggghts.log in the output directory.
#include "demlink/server/backend/liggghts_backend.hpp"

#include <liggghts/library.h>
#include <mpi.h>
#include <unistd.h>
#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <vector>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/checkpoint_file.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/server/backend/liggghts_flows.hpp"
#include "demlink/server/backend/liggghts_motion.hpp"
#include "demlink/server/backend/liggghts_script.hpp"
#include "demlink/server/run/frame_series.hpp"
#include "demlink/server/run/run_driver.hpp"

namespace demlink::server {
namespace {

void finalizeMpi() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized == 0) MPI_Finalize();
}

/// A LIGGGHTS input file in the temporary folder, unique per process.
std::filesystem::path scratchFilePath(const std::string& extension) {
  static int counter = 0;
  return std::filesystem::temp_directory_path() /
         fmt::format("demlink-liggghts-{}-{}.{}", static_cast<long>(::getpid()), counter++, extension);
}

bool writeFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  return out.good();
}

/// The first N values of a LIGGGHTS fix's global vector.
template <std::size_t N>
std::array<double, N> fixVector(void* lammps, const std::string& id) {
  std::array<double, N> values{};
  for (std::size_t i = 0; i < N; ++i) {
    auto* value = static_cast<double*>(lammps_extract_fix(lammps, id.c_str(), 0, 1, static_cast<int>(i), 0));
    if (value == nullptr) throw std::runtime_error("LIGGGHTS has no fix " + id);
    values[i] = *value;
    std::free(value);  // lammps_extract_fix returns a malloc'd copy of a global value
  }
  return values;
}

}  // namespace

int ensureMpi() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized == 0) {
    int provided = MPI_THREAD_SINGLE;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_MULTIPLE, &provided);
    std::atexit(finalizeMpi);
  }
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

bool mpiCallsFromAnyThread() {
  int level = MPI_THREAD_SINGLE;
  MPI_Query_thread(&level);
  return level >= MPI_THREAD_SERIALIZED;
}

int mpiRanks() {
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  return ranks;
}

LiggghtsBackend::LiggghtsBackend(core::World& world, const std::string& logFile, const std::filesystem::path& restore)
    : world_(world) {
  const int rank = ensureMpi();
  if (!world_.initialized()) world_.initialize();
  step_ = world_.stepCount();
  std::filesystem::path restartFile;
  if (restore.empty()) {
    for (const std::uint64_t id : world_.particles().id) {  // read_data gives slot k tag k + 1
      tag_ids_.push_back(id);
      tag_of_id_.emplace(id, tag_ids_.size());
    }
  } else {
    restoreTagMap(restore);
    restartFile = std::filesystem::path(restore).replace_extension(".liggghts");
    if (!std::filesystem::exists(restartFile)) {
      throw core::InputError("restore", restore.string(),
                             "the LIGGGHTS restart file " + restartFile.string() + " that belongs to it is missing");
    }
  }
  // Rank 0 writes the data file (read_data reads it there only); every rank writes its own
  // copy of the meshes, whichever rank LIGGGHTS reads them on.
  const std::filesystem::path data = scratchFilePath("data");
  std::vector<std::filesystem::path> meshPaths;
  std::vector<std::string> meshFiles;
  for (std::size_t k = 0; k < world_.meshes().size(); ++k) {
    meshPaths.push_back(scratchFilePath("stl"));
    meshFiles.push_back(meshPaths.back().string());
  }
  std::vector<std::string> commands =
      liggghtsCommands(world_, data.string(), meshFiles, restartFile.string());  // may refuse
  const std::vector<std::string> sources = liggghtsSourceCommands(world_);                // may refuse
  commands.insert(commands.end(), sources.begin(), sources.end());
  int ok = 1;
  if (rank == 0 && restore.empty()) ok = writeFile(data, liggghtsDataFile(world_)) ? 1 : 0;
  for (std::size_t k = 0; k < meshPaths.size(); ++k) {
    if (!writeFile(meshPaths[k], liggghtsStl(world_.meshes()[k]))) ok = 0;
  }
  int allOk = 0;
  MPI_Allreduce(&ok, &allOk, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (allOk == 0) throw std::runtime_error("cannot write LIGGGHTS input files to " + data.parent_path().string());
  // Screen output to /dev/null, not "none": LIGGGHTS 3.8's STL reader prints to the screen
  // without checking it exists (fix mesh/surface crashes with -screen none).
  std::vector<std::string> args = {"liggghts", "-screen", "/dev/null", "-log", logFile.empty() ? "none" : logFile};
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  lammps_open(static_cast<int>(argv.size()), argv.data(), MPI_COMM_WORLD, &lammps_);
  for (const std::string& line : commands) command(line);
  // The move fixes' variables come before any other (liggghts_motion.hpp).
  motions_.resize(world_.meshes().size());
  for (std::size_t k = 0; k < motions_.size(); ++k) {
    for (const std::string& line : liggghtsMeshMotionSetup(k)) command(line);
  }
  // The insertion fixes as created (a restored fix may start from its restart's counters,
  // which the restored sources' reports hold already).
  for (const auto& component : world_.components()) {
    if (auto* source = dynamic_cast<core::ParticleSource*>(component.get())) {
      SourceFix fix;
      fix.source = source;
      fix.rate = liggghtsSourceRate(*source);
      fix.active = !liggghtsInsertCommand(world_, *source, sources_.size(), 0).empty();
      if (fix.active) {
        const std::array<double, 2> counters = fixVector<2>(lammps_, liggghtsInsertFix(sources_.size(), 0));
        fix.counted = static_cast<std::uint64_t>(std::llround(counters[0]));
        fix.counted_mass = counters[1];
      }
      sources_.push_back(fix);
    }
  }
  MPI_Barrier(MPI_COMM_WORLD);
  std::error_code ignored;
  std::filesystem::remove(data, ignored);
  for (const std::filesystem::path& path : meshPaths) std::filesystem::remove(path, ignored);
  if (const std::size_t read = particleCount(); read != world_.particles().size()) {
    lammps_close(lammps_);  // the destructor does not run for a constructor that throws
    lammps_ = nullptr;
    throw std::runtime_error(fmt::format("LIGGGHTS read {} of the scene's {} particles ({})", read,
                                         world_.particles().size(),
                                         restore.empty() ? "outside the bounds?" : "restart and checkpoint disagree"));
  }
  if (!restore.empty()) {
    const auto ntimestep = *static_cast<std::int64_t*>(lammps_extract_global(lammps_, "ntimestep"));
    if (static_cast<std::uint64_t>(ntimestep) != step_) {
      throw core::InputError("restore", restore.string(),
                             fmt::format("its LIGGGHTS restart is at step {}, the checkpoint at step {}", ntimestep,
                                         step_));
    }
  }
}

namespace {
// Version 2: the lost particles left the tag map (the world's removedAtBounds() in `.bin`
// holds them); version 1 ("DEMLLGID") files are refused by name.
constexpr char kTagMapMagic[9] = "DEMLLGI2";
constexpr char kTagMapMagicV1[9] = "DEMLLGID";
}  // namespace

void LiggghtsBackend::writeCheckpoint(const std::filesystem::path& base) {
  const std::filesystem::path restart = std::filesystem::path(base).replace_extension(".liggghts");
  command("write_restart " + restart.string());
  // write_restart migrates the atoms and rebuilds the ghosts (comm exchange and borders)
  // but not the neighbour lists: a run without set-up would pair atoms with the wrong
  // ghosts (on more than one rank). The next run sets up, as a restored run does.
  started_ = false;
  if (ensureMpi() == 0) {
    core::writeCheckpointFile(world_, std::filesystem::path(base).replace_extension(".bin"));
    core::StateWriter out;
    out.writeBytes(kTagMapMagic, 8);
    out.section("LTAG", [&] {
      out.write<std::uint64_t>(step_);
      out.writeVector(tag_ids_);
      out.write<std::uint64_t>(inserted_.count);
      out.write<double>(inserted_.mass);
    });
    const std::filesystem::path ids = std::filesystem::path(base).replace_extension(".liggghts_ids");
    if (!writeFile(ids, out.bytes())) throw std::runtime_error("cannot write " + ids.string());
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

void LiggghtsBackend::restoreTagMap(const std::filesystem::path& restore) {
  const std::filesystem::path path = std::filesystem::path(restore).replace_extension(".liggghts_ids");
  const std::string bytes = core::readCheckpointBytes(path);
  core::StateReader file(bytes, path.string(), "header");
  char magic[8] = {};
  file.readBytes(magic, 8);
  if (std::string_view(magic, 8) == std::string_view(kTagMapMagicV1, 8)) {
    file.fail("magic", "a LIGGGHTS tag map of an older DEMLink (it counted lost particles apart); write the "
                       "checkpoint again with this version");
  }
  if (std::string_view(magic, 8) != std::string_view(kTagMapMagic, 8)) file.fail("magic", "not a LIGGGHTS tag map");
  core::StateReader in = file.section("LTAG", "tag map");
  core::requireEqual(in, "step", in.read<std::uint64_t>(), step_);
  tag_ids_ = in.readVector<std::uint64_t>();
  inserted_.count = in.read<std::uint64_t>();
  inserted_.mass = in.read<double>();
  in.requireEnd();
  // The map of the particles the world still holds (those sinks removed or LIGGGHTS lost
  // keep their tag in tag_ids_, so a tag is never given to a new particle twice).
  std::unordered_map<std::uint64_t, std::size_t> tagOfId;
  for (std::size_t tag = 1; tag <= tag_ids_.size(); ++tag) tagOfId.emplace(tag_ids_[tag - 1], tag);
  for (const std::uint64_t id : world_.particles().id) {
    const auto found = tagOfId.find(id);
    if (found == tagOfId.end()) file.fail(std::to_string(id), "the checkpoint's particle id has no LIGGGHTS tag");
    tag_of_id_.emplace(id, found->second);
  }
}

LiggghtsBackend::~LiggghtsBackend() {
  if (lammps_ != nullptr) lammps_close(lammps_);
}

void LiggghtsBackend::command(const std::string& line) {
  spdlog::debug("liggghts: {}", line);
  lammps_command(lammps_, line.c_str());
}

bool LiggghtsBackend::updateMeshMotion() {
  bool created = false;
  const double dt = world_.settings().time_step;
  for (std::size_t k = 0; k < motions_.size(); ++k) {
    const core::MeshBody& mesh = world_.meshes()[k];
    MeshMotion& motion = motions_[k];
    if (mesh.linearVelocity() == motion.linear && mesh.angularVelocity() == motion.angular) continue;
    for (const std::string& line : liggghtsMeshTwist(k, mesh.linearVelocity(), mesh.angularVelocity(), dt)) {
      command(line);
    }
    if (!motion.fixed) {
      for (const LiggghtsFix& fix : liggghtsMeshMotionFixes(k, mesh.position())) command(fix.command);
      motion.fixed = true;
      created = true;
    }
    motion.linear = mesh.linearVelocity();
    motion.angular = mesh.angularVelocity();
  }
  return created;
}

void LiggghtsBackend::countInserted() {
  for (std::size_t k = 0; k < sources_.size(); ++k) {
    SourceFix& fix = sources_[k];
    if (!fix.active) continue;
    const std::array<double, 2> counters = fixVector<2>(lammps_, liggghtsInsertFix(k, fix.generation));
    const auto count = static_cast<std::uint64_t>(std::llround(counters[0]));
    fix.source->countInsertedElsewhere(count - fix.counted, counters[1] - fix.counted_mass);
    fix.counted = count;
    fix.counted_mass = counters[1];
  }
}

bool LiggghtsBackend::updateSources() {
  bool changed = false;
  for (std::size_t k = 0; k < sources_.size(); ++k) {
    SourceFix& fix = sources_[k];
    if (liggghtsSourceRate(*fix.source) == fix.rate) continue;
    countInserted();
    if (fix.active) command("unfix " + liggghtsInsertFix(k, fix.generation));
    // A new id: a fix of an old id would take that id's state from a restart file.
    ++fix.generation;
    const std::string insert = liggghtsInsertCommand(world_, *fix.source, k, fix.generation);
    if (!insert.empty()) command(insert);
    fix.rate = liggghtsSourceRate(*fix.source);
    fix.active = !insert.empty();
    fix.counted = 0;
    fix.counted_mass = 0.0;
    changed = true;
  }
  return changed;
}

void LiggghtsBackend::advanceTo(std::uint64_t step) {
  if (step <= step_) return;
  // The first run sets up neighbour lists and forces; later ones continue exactly where
  // the last stopped (pre no: no re-setup), as one uninterrupted run would. A new move
  // fix is only seen by a run that sets up (LIGGGHTS builds its fix lists there); the
  // set-up recomputes the forces at the same positions, which changes nothing. A changed
  // twist of a mesh whose fixes exist needs none: they read it from variables each step.
  // A fix made or deleted (a source's or a mesh's) is only seen by a run that sets up.
  const bool sourcesChanged = updateSources();
  const bool refixed = updateMeshMotion() || sourcesChanged;
  command(fmt::format("run {}{}", step - step_, started_ && !refixed ? " pre no post no" : " post no"));
  started_ = true;
  const std::uint64_t steps = step - step_;
  step_ = step;
  world_.advanceClockTo(step);
  for (std::size_t k = 0; k < world_.meshes().size(); ++k) {
    core::MeshBody& mesh = world_.mesh(k);
    mesh.advance(static_cast<double>(steps) * world_.settings().time_step);
    const auto [force, torque] = meshWrench(k);
    mesh.clearWrench();
    mesh.addWrench(force, torque);
  }
}

std::size_t LiggghtsBackend::particleCount() const {
  const int local = *static_cast<int*>(lammps_extract_global(lammps_, "nlocal"));
  long long total = 0;
  const long long mine = local;
  MPI_Allreduce(&mine, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  return static_cast<std::size_t>(total);
}

double LiggghtsBackend::particleMass() const {
  const int local = *static_cast<int*>(lammps_extract_global(lammps_, "nlocal"));
  const auto* rmass = static_cast<const double*>(lammps_extract_atom(lammps_, "rmass"));
  double mine = 0.0;
  for (int i = 0; i < local; ++i) mine += rmass[i];
  double total = 0.0;
  MPI_Allreduce(&mine, &total, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return total;
}

void LiggghtsBackend::syncParticles() {
  // Every rank packs its atoms as (tag, type, radius, mass, x, v, omega, f); all ranks
  // receive all of them. f is the last force evaluation's, fix gravity's m g included.
  constexpr int kRow = 16;
  const int local = *static_cast<int*>(lammps_extract_global(lammps_, "nlocal"));
  const auto* tags = static_cast<const int*>(lammps_extract_atom(lammps_, "id"));
  const auto* types = static_cast<const int*>(lammps_extract_atom(lammps_, "type"));
  const auto* radius = static_cast<const double*>(lammps_extract_atom(lammps_, "radius"));
  const auto* rmass = static_cast<const double*>(lammps_extract_atom(lammps_, "rmass"));
  const auto* const* x = static_cast<double**>(lammps_extract_atom(lammps_, "x"));
  const auto* const* v = static_cast<double**>(lammps_extract_atom(lammps_, "v"));
  const auto* const* omega = static_cast<double**>(lammps_extract_atom(lammps_, "omega"));
  const auto* const* force = static_cast<double**>(lammps_extract_atom(lammps_, "f"));
  std::vector<double> mine;
  mine.reserve(static_cast<std::size_t>(local) * kRow);
  for (int i = 0; i < local; ++i) {
    mine.insert(mine.end(), {static_cast<double>(tags[i]), static_cast<double>(types[i]), radius[i], rmass[i]});
    for (const auto* column : {x, v, omega, force}) mine.insert(mine.end(), column[i], column[i] + 3);
  }
  const int ranks = mpiRanks();
  std::vector<int> counts(static_cast<std::size_t>(ranks));
  const int count = static_cast<int>(mine.size());
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::vector<int> offsets(static_cast<std::size_t>(ranks), 0);
  for (std::size_t r = 1; r < offsets.size(); ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<double> all(static_cast<std::size_t>(offsets.back() + counts.back()));
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                 MPI_COMM_WORLD);
  // Our particle with stable id tag_ids_[t - 1] is LIGGGHTS's atom t; atoms LIGGGHTS lost
  // (outside the box) leave the world as our engine removes them at the bounds.
  std::size_t largestTag = tag_ids_.size();
  for (std::size_t row = 0; row < all.size(); row += kRow) {
    largestTag = std::max(largestTag, static_cast<std::size_t>(all[row]));
  }
  std::vector<const double*> rowOfTag(largestTag + 1, nullptr);
  for (std::size_t row = 0; row < all.size(); row += kRow) {
    rowOfTag[static_cast<std::size_t>(all[row])] = &all[row + 1];
  }
  core::ParticleArrays& p = world_.particles();
  world_.removeParticlesAtBoundsIf([&](auto slot) { return rowOfTag[tag_of_id_.at(p.id[slot])] == nullptr; });
  // Our force array holds the contact force alone (trackers report it): LIGGGHTS's less m g.
  const core::Vec3 g = world_.gravity();
  const auto contactForce = [&g](const double* row) -> core::Vec3 {
    return {row[12] - row[2] * g.x(), row[13] - row[2] * g.y(), row[14] - row[2] * g.z()};
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double* row = rowOfTag[tag_of_id_.at(p.id[i])];
    p.position[i] = core::Vec3(row[3], row[4], row[5]);
    p.velocity[i] = core::Vec3(row[6], row[7], row[8]);
    p.angular_velocity[i] = core::Vec3(row[9], row[10], row[11]);
    p.force[i] = contactForce(row);
  }
  // Atoms with tags we have not seen were inserted by a source: they join the world in tag
  // order (the same on every rank and for any number of ranks).
  constexpr std::uint64_t kNoParticle = std::numeric_limits<std::uint64_t>::max();
  const std::size_t known = tag_ids_.size();
  tag_ids_.resize(largestTag, kNoParticle);
  for (std::size_t tag = known + 1; tag <= largestTag; ++tag) {
    const double* row = rowOfTag[tag];
    if (row == nullptr) continue;  // inserted and lost within one stride
    core::ParticleSpec spec;
    spec.material = static_cast<std::uint32_t>(row[0]) - 1;
    spec.radius = row[1];
    spec.position = core::Vec3(row[3], row[4], row[5]);
    spec.velocity = core::Vec3(row[6], row[7], row[8]);
    spec.angular_velocity = core::Vec3(row[9], row[10], row[11]);
    const std::uint64_t id = world_.addParticle(spec, "LIGGGHTS insertion");
    p.force.back() = contactForce(row);
    tag_ids_[tag - 1] = id;
    tag_of_id_.emplace(id, tag);
    ++inserted_.count;
    inserted_.mass += p.mass.back();
  }
  countInserted();
  // advanceTo() has moved the clock and set the mesh wrenches.
  const std::vector<std::uint64_t> removed = runLiggghtsComponents(world_);
  if (removed.empty()) return;
  // Delete the atoms our sinks removed; the next run sets LIGGGHTS up again (its neighbour
  // lists still hold them).
  constexpr std::size_t kIdsPerCommand = 500;
  for (std::size_t first = 0; first < removed.size(); first += kIdsPerCommand) {
    std::string line = "group demlink_sunk id";
    for (std::size_t k = first; k < std::min(removed.size(), first + kIdsPerCommand); ++k) {
      line += fmt::format(" {}", tag_of_id_.at(removed[k]));
    }
    command(line);
  }
  command("delete_atoms group demlink_sunk compress no");
  command("group demlink_sunk delete");
  for (const std::uint64_t id : removed) tag_of_id_.erase(id);
  started_ = false;
}

std::pair<std::uint64_t, double> LiggghtsBackend::sourceInserted(std::size_t source) const {
  const core::SourceReport& report = sources_.at(source).source->report();
  return {report.inserted_count, report.inserted_mass};
}

std::pair<core::Vec3, core::Vec3> LiggghtsBackend::meshWrench(std::size_t mesh) const {
  const std::array<double, 6> values = fixVector<6>(lammps_, liggghtsMeshFix(mesh));
  return {core::Vec3(values[0], values[1], values[2]), core::Vec3(values[3], values[4], values[5])};
}

RunSummary runHeadlessLiggghts(const v1::Scene& declarations, TranslatedScene& scene) {
  core::World& world = scene.world;
  const RunOptions& run = scene.run;
  const std::string& box = run.field_prefix;
  const int rank = ensureMpi();
  if (run.output_directory.empty()) {
    throw core::InputError(box + ".output.directory", "\"\"", "no output directory given");
  }
  if (!world.initialized()) world.initialize();
  requireLiggghtsCompatible(declarations, world);
  if (!run.restore_file.empty()) {
    core::restoreCheckpointFile(world, run.restore_file);
    spdlog::info("restored {} at t = {:.6g} s ({} particles)", run.restore_file, world.time(),
                 world.particles().size());
  }
  const RunPlan plan = planRun(run, world.settings().time_step, true);
  for (const std::string& warning : plan.warnings) spdlog::warn("{}", warning);
  if (world.stepCount() >= plan.end_step) {
    throw core::InputError(box + ".end_time", core::formatValue(run.end_time),
                           "the restored checkpoint is already at t = " + core::formatValue(world.time()) +
                               " s; nothing left to run");
  }
  const std::filesystem::path directory = run.output_directory;
  // Rank 0 writes every output with the native run's driver (frames, summary.csv, a CSV
  // per sink and sensor, run_log.csv, the final CSV); a checkpoint is a collective
  // (LiggghtsBackend::writeCheckpoint), so the other ranks take part in each one the plan
  // schedules, in the same order.
  std::optional<RunDriver> driver;
  if (rank == 0) driver.emplace(world, run, plan, directory, box + ".output.directory");
  MPI_Barrier(MPI_COMM_WORLD);

  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t startStep = world.stepCount();
  LiggghtsBackend backend(world, (directory / "liggghts.log").string(), run.restore_file);
  spdlog::info("LIGGGHTS backend: {} particles, {} materials, {} planes on {} MPI rank(s); {} steps of {:.4g} s",
               world.particles().size(), world.materials().size(), world.planes().size(), mpiRanks(), plan.end_step,
               world.settings().time_step);
  const std::uint64_t frameEvery = plan.frame_every > 0 ? plan.frame_every : plan.end_step;
  const std::uint64_t checkpointEvery = plan.checkpoint_every;
  const std::uint64_t stride =
      liggghtsStride(world, checkpointEvery > 0 ? std::gcd(frameEvery, checkpointEvery) : frameEvery);
  prepareLiggghtsComponents(world, stride);
  std::uint64_t checkpoints = 0;
  const auto checkpoint = [&](const std::filesystem::path& path) {
    backend.writeCheckpoint(path);
    ++checkpoints;
  };
  try {
    if (driver) {
      driver->setCheckpointWriter(checkpoint);
      driver->start(world);
    }
    while (backend.stepCount() < plan.end_step) {
      backend.advanceTo(std::min(plan.end_step, (backend.stepCount() / stride + 1) * stride));
      backend.syncParticles();
      const std::uint64_t step = backend.stepCount();
      if (driver) {
        driver->afterStep(world);
      } else if (plan.checkpointDue(step)) {
        checkpoint(directory / plan.checkpointName(step));
      }
      if (!plan.frameDue(step)) continue;
      const FrameStats stats = frameStats(world);
      spdlog::info("t = {:.4f} s | {} particles ({} inserted, {} lost at the box) | kinetic energy {:.4g} J | "
                   "mean z {:.6g} m | max z {:.6g} m",
                   backend.time(), stats.particles, backend.insertedParticles().count, world.removedAtBounds().count,
                   stats.kinetic_energy, stats.mean_z, stats.max_z);
    }
    if (driver) {
      driver->finish(world);
    } else if (run.final_checkpoint) {
      checkpoint(directory / core::kFinalCheckpointFileName);
    }
  } catch (const std::exception& error) {
    if (driver) driver->abort(error.what());
    throw;
  }
  for (std::size_t k = 0; k < backend.sourceCount(); ++k) {
    const auto [count, mass] = backend.sourceInserted(k);
    spdlog::info("LIGGGHTS source {}: {} particles, {:.6g} kg inserted", k, count, mass);
  }

  RunSummary summary;
  summary.steps = backend.stepCount() - startStep;
  summary.frames = driver ? driver->frameCount() : 0;
  summary.checkpoints = checkpoints;
  summary.final_particles = world.particles().size();
  summary.final_time = backend.time();
  summary.final_kinetic_energy = world.kineticEnergy();
  summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary.output_directory = directory;
  spdlog::info("finished on LIGGGHTS: {} steps to t = {:.6g} s in {:.3g} s wall", summary.steps, summary.final_time,
               summary.wall_seconds);
  return summary;
}

}  // namespace demlink::server
