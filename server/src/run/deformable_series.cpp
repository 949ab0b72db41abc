/// Deformable body outputs (contract in deformable_series.hpp).
///
/// Displacements are those of the body (from the initial configuration); a mass-spring
/// body's nodes are all surface nodes, an FEM body's .vtu lists every node.
#include "demlink/server/run/deformable_series.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "demlink/core/deformable/fem_body.hpp"
#include "demlink/core/deformable/mass_spring_body.hpp"
#include "demlink/core/output/csv_table.hpp"
#include "demlink/core/step/watchdog.hpp"

namespace demlink::server {
namespace {

std::string vec(const core::Vec3& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x(), v.y(), v.z()); }

/// Node displacements and velocities of the first `count` nodes.
void nodeStates(const core::DeformableBody& body, std::size_t count, std::vector<core::Vec3>& positions,
                std::vector<core::Vec3>& displacements, std::vector<core::Vec3>& velocities) {
  positions.resize(count);
  displacements.resize(count);
  velocities.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    positions[i] = body.nodePosition(i);
    displacements[i] = body.nodeDisplacement(i);
    velocities[i] = body.nodeVelocity(i);
  }
}

/// A frame is checked before it is written (the watchdog reads the world only every few
/// steps): a non-finite node or stress stops the run as the watchdog would, and no file
/// gets a NaN.
void requireFiniteFrame(const core::DeformableBody& body, std::uint64_t step, const std::vector<core::Vec3>& positions,
                        const std::vector<core::Vec3>& velocities, const std::vector<double>& stress) {
  const auto finite = [](const core::Vec3& v) { return v.allFinite(); };
  std::string what;
  if (!std::all_of(positions.begin(), positions.end(), finite)) what = "node positions";
  if (what.empty() && !std::all_of(velocities.begin(), velocities.end(), finite)) what = "node velocities";
  if (what.empty() && !std::all_of(stress.begin(), stress.end(), [](double s) { return std::isfinite(s); })) {
    what = "von Mises stress";
  }
  if (!what.empty()) {
    throw core::SimulationFault("non_finite",
                                std::string(body.kind()) + " body " + body.name() + " (" + what +
                                    "); its frame is not written",
                                step);
  }
}

}  // namespace

std::vector<std::string> deformableReportLines(const core::World& world) {
  std::vector<std::string> lines;
  for (const auto& body : world.deformableBodies()) {
    std::string springs;
    if (const auto* ms = dynamic_cast<const core::MassSpringBody*>(body.get())) {
      springs = fmt::format(", {} springs", ms->springs().size());
    } else if (const auto* fem = dynamic_cast<const core::FemBody*>(body.get())) {
      springs = fmt::format(", {} elements", fem->elements().size());
    }
    lines.push_back(fmt::format("deformable {} ({}): {} nodes ({} on the surface){}, {} triangles, mass {:.6g} kg, "
                                "critical time step {} ({})",
                                body->name(), body->kind(), body->nodeCount(), body->surface().positions().size(),
                                springs, body->surface().triangles().size(), body->totalMass(),
                                std::isfinite(body->criticalTimeStep())
                                    ? fmt::format("{:.4g} s", body->criticalTimeStep())
                                    : std::string("no limit"),
                                body->criticalTimeStepReason()));
  }
  return lines;
}

std::vector<std::string> deformableFinalLines(const core::World& world) {
  std::vector<std::string> lines;
  for (const auto& body : world.deformableBodies()) {
    const core::NodeReaction fixed = body->fixedReaction();
    const core::NodeReaction driven = body->drivenReaction();
    lines.push_back(fmt::format("deformable {} ({}): {} broken springs, kinetic energy {:.4g} J, fixed reaction {} N, "
                                "driven reaction {} N",
                                body->name(), body->kind(), body->brokenCount(), body->kineticEnergy(),
                                vec(fixed.force), vec(driven.force)));
  }
  return lines;
}

DeformableSeries::DeformableSeries(const std::filesystem::path& directory, const core::World& world)
    : directory_(directory), entries_(world.deformableBodies().size()), broken_written_(entries_.size(), 0) {
  bool anyMassSpring = false;
  for (std::size_t b = 0; b < entries_.size(); ++b) {
    if (const auto* ms = dynamic_cast<const core::MassSpringBody*>(world.deformableBodies()[b].get())) {
      anyMassSpring = true;
      broken_written_[b] = ms->brokenSprings().size();
    }
  }
  if (!anyMassSpring) return;
  const std::filesystem::path csv = directory_ / "broken_springs.csv";
  broken_.open(csv, std::ios::trunc);
  if (!broken_) throw std::runtime_error("cannot write " + csv.string());
  broken_ << "time_s,body,spring,x_m,y_m,z_m,force_N,strain\n";
  broken_.flush();
}

void DeformableSeries::writeFrame(const core::World& world) {
  std::vector<core::Vec3> positions;
  std::vector<core::Vec3> displacements;
  std::vector<core::Vec3> velocities;
  for (std::size_t b = 0; b < entries_.size(); ++b) {
    const core::DeformableBody& body = *world.deformableBodies()[b];
    const core::DeformableSurface& surface = body.surface();
    const auto* fem = dynamic_cast<const core::FemBody*>(&body);
    const bool volume = fem != nullptr && !fem->elements().empty();
    const std::string file = fmt::format("deformable_{}_{:06}.{}", body.name(), entries_[b].size(), volume ? "vtu" : "vtp");
    const std::string path = (directory_ / file).string();
    if (volume) {
      nodeStates(body, body.nodeCount(), positions, displacements, velocities);
      const std::vector<double> stress = fem->vonMisesStress();
      requireFiniteFrame(body, world.stepCount(), positions, velocities, stress);
      core::writeTetrahedraVtu(path, positions, displacements, velocities, fem->elements(), stress);
    } else {
      nodeStates(body, surface.positions().size(), positions, displacements, velocities);
      requireFiniteFrame(body, world.stepCount(), positions, velocities, {});
      std::vector<std::array<std::uint32_t, 2>> springs;
      std::vector<char> intact;
      if (const auto* ms = dynamic_cast<const core::MassSpringBody*>(&body)) {
        for (const core::SpringSpec& s : ms->springs()) springs.push_back({s.a, s.b});
        intact = ms->intact();
      }
      core::writeDeformableVtp(path, {positions, displacements, velocities, springs, intact, surface.triangles(),
                                      surface.active()});
    }
    entries_[b].push_back({world.time(), file});
    core::writePvd((directory_ / fmt::format("deformable_{}.pvd", body.name())).string(), entries_[b]);
  }
}

void DeformableSeries::afterStep(const core::World& world) {
  for (std::size_t b = 0; b < entries_.size(); ++b) {
    const auto* ms = dynamic_cast<const core::MassSpringBody*>(world.deformableBodies()[b].get());
    if (ms == nullptr || ms->brokenSprings().size() == broken_written_[b]) continue;
    for (std::size_t k = broken_written_[b]; k < ms->brokenSprings().size(); ++k) {
      const core::BrokenSpring& s = ms->brokenSprings()[k];
      broken_ << fmt::format("{},{},{},{},{},{},{},{}\n", core::csvNumber(s.time), ms->name(), s.spring,
                             core::csvNumber(s.position.x()), core::csvNumber(s.position.y()),
                             core::csvNumber(s.position.z()), core::csvNumber(s.force), core::csvNumber(s.strain));
    }
    broken_written_[b] = ms->brokenSprings().size();
    broken_.flush();
    if (!broken_) throw std::runtime_error("cannot write " + (directory_ / "broken_springs.csv").string());
  }
}

}  // namespace demlink::server
