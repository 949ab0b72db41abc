/// Node tracker (contract in node_tracker.hpp). Its checkpoint state is the sample
/// schedule of SampledComponent: a sample reads the bodies, which restore their own state.
#include "demlink/core/components/node_tracker.hpp"

#include <cmath>

#include "demlink/core/deformable/deformable_body.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/step/watchdog.hpp"
#include "demlink/core/components/component_world.hpp"

namespace demlink::core {
namespace {

void appendVector(std::vector<double>& row, const Vec3& v) { row.insert(row.end(), {v.x(), v.y(), v.z()}); }

}  // namespace

NodeTracker::NodeTracker(std::string name, std::vector<TrackedNode> nodes, SampleSchedule schedule,
                         std::string fieldPrefix)
    : SampledComponent(std::move(name), schedule, std::move(fieldPrefix)), nodes_(std::move(nodes)) {
  if (nodes_.empty()) throw InputError(this->fieldPrefix() + ".nodes", "[]", "a node tracker needs a node");
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    for (std::size_t j = 0; j < k; ++j) {
      if (nodes_[j].body == nodes_[k].body && nodes_[j].node == nodes_[k].node) {
        throw InputError(this->fieldPrefix() + ".nodes[" + std::to_string(k) + "]", std::to_string(nodes_[k].node),
                         "node listed twice");
      }
    }
  }
}

void NodeTracker::initialize(ComponentWorld& world) {
  labels_.clear();
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    const std::string field = fieldPrefix() + ".nodes[" + std::to_string(k) + "]";
    if (nodes_[k].body >= world.deformableBodies().size()) {
      throw InputError(field, std::to_string(nodes_[k].body), "no such deformable body");
    }
    const DeformableBody& body = *world.deformableBodies()[nodes_[k].body];
    if (nodes_[k].node >= body.nodeCount()) {
      throw InputError(field, body.name() + ":" + std::to_string(nodes_[k].node),
                       "no such node (" + std::to_string(body.nodeCount()) + " nodes)");
    }
    std::string label = body.name() + "_" + std::to_string(nodes_[k].node);
    for (char& c : label) {
      if (c == ',' || c == '"' || c == '\n' || c == '\r' || c == ' ') c = '_';
    }
    labels_.push_back(std::move(label));
  }
  resolveSchedule(world);
  sample(world);
}

void NodeTracker::observe(const ComponentWorld& world) {
  if (sampleDue(world)) sample(world);
}

std::vector<std::string> NodeTracker::columns() const {
  std::vector<std::string> out{"time_s"};
  for (const std::string& label : labels_) {
    for (const char* suffix : {"_x_m", "_y_m", "_z_m", "_ux_m", "_uy_m", "_uz_m", "_vx_m_s", "_vy_m_s", "_vz_m_s"}) {
      out.push_back(label + suffix);
    }
  }
  return out;
}

void NodeTracker::sample(const ComponentWorld& world) {
  std::vector<double> row{world.time()};
  for (const TrackedNode& tracked : nodes_) {
    const DeformableBody& body = *world.deformableBodies()[tracked.body];
    appendVector(row, body.nodePosition(tracked.node));
    appendVector(row, body.nodeDisplacement(tracked.node));
    appendVector(row, body.nodeVelocity(tracked.node));
  }
  // The watchdog reads the world only every few steps: a row between two readings is
  // checked here, so a NaN never reaches the file (every value of a node row is defined).
  for (std::size_t column = 1; column < row.size(); ++column) {
    if (!std::isfinite(row[column])) {
      const TrackedNode& tracked = nodes_[(column - 1) / 9];
      throw SimulationFault("non_finite",
                            "node_tracker " + name() + ": node " + std::to_string(tracked.node) + " of body " +
                                world.deformableBodies()[tracked.body]->name() +
                                " (position, displacement or velocity); the row is not written",
                            world.stepCount());
    }
  }
  publish(world, std::move(row));
}

}  // namespace demlink::core
