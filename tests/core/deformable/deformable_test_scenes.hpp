#pragma once
/// Mass-spring scenes shared by the deformable-body tests.
#include <algorithm>
#include <memory>
#include <string>

#include "demlink/core/deformable/mass_spring_body.hpp"
#include "demlink/core/world.hpp"

namespace demlink::core::test {

/// What settleInWindows saw in its last window.
struct SettledWindow {
  double motion_max = 0.0;     ///< largest motion() over the window
  double mean_reaction = 0.0;  ///< reaction() averaged over the window
  int steps = 0;               ///< steps taken in all
};

/// Steps `world` in windows of `window` steps until the largest value of motion() over a
/// window is at most `settled`, or `maxWindows` windows have passed. Averaging the reaction
/// over a whole settled window keeps a residual oscillation out of the figure.
template <class Motion, class Reaction>
SettledWindow settleInWindows(World& world, int window, double settled, int maxWindows, Motion motion,
                              Reaction reaction) {
  SettledWindow w;
  do {
    w.motion_max = 0.0;
    w.mean_reaction = 0.0;
    for (int k = 0; k < window; ++k, ++w.steps) {
      world.step();
      w.motion_max = std::max(w.motion_max, motion());
      w.mean_reaction += reaction() / window;
    }
  } while (w.motion_max > settled && w.steps < maxWindows * window);
  return w;
}

/// A square sheet in the plane z = height, side `side` [m] centred on the origin, nodes
/// `spacing` apart, with shear and bending springs; nodes within `pin` of its edge fixed
/// (pin < 0: the four corners only; 0: none); `nodeDamping` [1/s] drags every free node.
inline MassSpringSpec sheetSpec(double side, double spacing, double height, double mass, double stiffness,
                                double damping, double pin, double nodeDamping = 0.0) {
  MassSpringSpec spec;
  spec.node_damping = nodeDamping;
  spec.name = "sheet";
  spec.total_mass = mass;
  spec.stiffness = stiffness;
  spec.damping = damping;
  spec.shear_factor = 0.5;
  spec.bending_factor = 0.1;
  const double h = 0.5 * side;
  spec.box = MassSpringSpec::Box{Vec3(-h, -h, height - 0.25 * spacing), Vec3(h, h, height + 0.25 * spacing), spacing};
  if (pin == 0.0) return spec;  // a free sheet
  const double reach = pin < 0.0 ? 0.1 * spacing : pin;
  for (const double sx : {-1.0, 1.0}) {
    if (pin < 0.0) {
      for (const double sy : {-1.0, 1.0}) {
        const Vec3 corner(sx * h, sy * h, height);
        spec.fixed_regions.push_back({corner - Vec3::Constant(reach), corner + Vec3::Constant(reach)});
      }
      continue;
    }
    // Edge strips x = +-h and y = +-h.
    const Vec3 r = Vec3::Constant(reach);
    spec.fixed_regions.push_back({Vec3(sx * h, -h, height) - r, Vec3(sx * h, h, height) + r});
    spec.fixed_regions.push_back({Vec3(-h, sx * h, height) - r, Vec3(h, sx * h, height) + r});
  }
  return spec;
}

}  // namespace demlink::core::test
