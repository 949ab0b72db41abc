#pragma once
/// What the live view shows of a world at one instant, copied out of the world on the
/// simulation thread so that encoding and sending never touch the world. Columns are
/// reused from one capture to the next (vector capacity only grows to the largest
/// particle count seen), so a capture allocates nothing once the run has peaked.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "demlink/core/world.hpp"

namespace demlink::server {

/// What colours the particles (the page's legend names it).
enum class ColourField : std::uint32_t { kSpeed = 0, kForce = 1, kMaterial = 2, kId = 3 };

/// Pose of a rigid mesh body: position [m] and orientation (x, y, z, w).
struct ViewPose {
  std::array<float, 3> position{};
  std::array<float, 4> orientation{0.0f, 0.0f, 0.0f, 1.0f};
};

/// A sensor's region now: kind (0 box, 1 sphere, 2 rectangle, 3 disc), half sizes
/// (box: half sides; sphere/disc: radius in [0]; rectangle: half length, half width) [m],
/// and its pose.
struct ViewRegion {
  std::uint32_t kind = 0;
  std::array<float, 3> half_size{};
  ViewPose pose;
};

/// A deformable body's surface now: node positions [m], per triangle whether it still
/// takes part in contacts (a torn mass-spring surface loses triangles), and for a
/// mass-spring body per spring whether it is intact (its nodes are all surface nodes, so
/// the springs index `positions`).
struct ViewSurface {
  std::vector<float> positions;  ///< x, y, z per node
  std::vector<std::uint8_t> triangle_active;
  std::vector<std::uint8_t> spring_intact;  ///< per spring of the scene's list; empty: no springs
};

/// The run's figures the overlay shows.
struct ViewStatus {
  double time = 0.0;              ///< simulated [s]
  std::uint64_t step = 0;         ///< [-]
  double real_time_factor = 0.0;  ///< simulated / wall seconds since the last capture [-]
  double steps_per_second = 0.0;  ///< since the last capture [1/s]
  double particle_mass = 0.0;     ///< in the world now [kg]
  double inserted_mass = 0.0;     ///< by sources so far [kg]
  double removed_mass = 0.0;      ///< by sinks and the domain bounds so far [kg]
  double initial_mass = 0.0;      ///< particle mass before any insertion or removal [kg]
};

struct ViewSnapshot {
  ViewStatus status;
  std::vector<float> position;  ///< x, y, z per particle [m]
  std::vector<float> radius;    ///< [m]
  std::vector<float> speed;     ///< |v| [m/s] (when a client colours by speed)
  std::vector<float> force;     ///< |F| contact force [N] (when a client colours by force)
  std::vector<std::uint32_t> material;
  std::vector<std::uint64_t> id;
  std::array<float, 3> box_lower{};  ///< the domain bounds, else the particles' box padded by the largest radius [m]
  std::array<float, 3> box_upper{};
  std::vector<ViewPose> meshes;      ///< per World::meshes()
  std::vector<ViewSurface> surfaces; ///< per World::deformableBodies()
  std::vector<ViewRegion> regions;   ///< region sensors, flow sensors and sinks, in component order

  [[nodiscard]] std::size_t particleCount() const { return radius.size(); }
};

/// Which optional columns a capture fills (the colour fields some client asked for).
struct CaptureFields {
  bool speed = false;
  bool force = false;
};

/// Copies the world's state into `snapshot` (status.time, step and masses too; the rate
/// figures and initial_mass are the caller's).
void captureSnapshot(const core::World& world, const CaptureFields& fields, ViewSnapshot& snapshot);

/// The parts of the scene that never change during a run, as JSON for the page: planes
/// (point, normal), mesh bodies (name, body-frame vertices, triangles), deformable
/// surfaces (name, triangles, a mass-spring body's springs as node pairs) and the region
/// list's names. Sent once per connection.
[[nodiscard]] std::string describeScene(const core::World& world);

}  // namespace demlink::server
