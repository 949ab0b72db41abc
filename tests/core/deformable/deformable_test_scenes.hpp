#pragma once
/// Mass-spring scenes shared by the deformable-body tests.
#include <memory>
#include <string>

#include "demlink/core/deformable/mass_spring_body.hpp"
#include "demlink/core/world.hpp"

namespace demlink::core::test {

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
