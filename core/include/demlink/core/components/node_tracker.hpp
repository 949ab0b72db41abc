#pragma once
/// A node tracker: records chosen nodes of deformable bodies (the solver paper's "particle
/// or FEM node" trackers) at a fixed sample interval: position, displacement from the
/// initial configuration and velocity of each node.
#include <cstdint>
#include <string>
#include <vector>

#include "demlink/core/components/sampled_component.hpp"

namespace demlink::core {

/// One tracked node: World::deformableBodies() index and node index of that body.
struct TrackedNode {
  std::size_t body = 0;
  std::size_t node = 0;
};

class NodeTracker final : public SampledComponent {
 public:
  /// Throws InputError naming fieldPrefix + ".nodes" when `nodes` is empty and
  /// fieldPrefix + ".nodes[k]" for a node listed twice. Bodies and node indices are
  /// checked by initialize().
  NodeTracker(std::string name, std::vector<TrackedNode> nodes, SampleSchedule schedule, std::string fieldPrefix);

  [[nodiscard]] std::string_view kind() const override { return "node_tracker"; }
  [[nodiscard]] StageSet stages() const override { return stageBit(Stage::kObserve); }
  void initialize(ComponentWorld& world) override;
  void observe(const ComponentWorld& world) override;
  /// time_s; per node <body>_<node>_{x,y,z}_m, _{ux,uy,uz}_m, _{vx,vy,vz}_m_s.
  [[nodiscard]] std::vector<std::string> columns() const override;

 private:
  void sample(const ComponentWorld& world);

  std::vector<TrackedNode> nodes_;
  std::vector<std::string> labels_;
};

}  // namespace demlink::core
