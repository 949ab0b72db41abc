#pragma once
/// Force stage loops: particle-particle (over the half neighbour list),
/// particle-plane (over each plane's near list) and particle-surface (over the
/// near list of each mesh or deformable body's surface). Templated on the contact law
/// and on whether rolling resistance is active, so the compiled loop contains
/// exactly what the scene uses; the world picks one instantiation at set-up
/// (contact_law_registry.hpp). Each loop checks that the per-contact history its
/// storage keeps is the one the law declares.
#include <ranges>
#include <type_traits>

#include "demlink/core/contact/contact_kernel.hpp"
#include "demlink/core/contact/contact_pair_table.hpp"
#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/walls/mesh_contact.hpp"
#include "demlink/core/walls/mesh_near_list.hpp"
#include "demlink/core/particles/neighbour_list.hpp"
#include "demlink/core/particles/particle_arrays.hpp"
#include "demlink/core/walls/plane_wall.hpp"

namespace demlink::core {

/// True when `Storage` (a near list's history column) holds Law::History per entry.
template <class Law, class Storage>
inline constexpr bool kHistoryStorageFits =
    std::is_same_v<typename Law::History, std::ranges::range_value_t<std::remove_cvref_t<Storage>>>;

/// Particle-particle contacts of rows [rowBegin, rowEnd) of the half list.
/// Forces and torques of slot s are added to force[s - base], torque[s - base]
/// (see PairLoopPartition for why every touched slot is >= base).
template <class Law, bool kRolling>
void particleContactRows(ParticleArrays& p, NeighbourList& list, const ContactPairTable& table, double dt,
                         std::size_t rowBegin, std::size_t rowEnd, Vec3* force, Vec3* torque, std::size_t base) {
  const std::span<const std::uint32_t> offsets = list.offsets();
  const std::span<const std::uint32_t> partners = list.partners();
  const std::span<Vec3> history = list.history();
  static_assert(kHistoryStorageFits<Law, decltype(list.history())>, "neighbour list history is not Law::History");
  const std::span<const ReducedPair> reduced = list.reduced();
  for (std::size_t i = rowBegin; i < rowEnd; ++i) {
    const Vec3 xi = p.position[i];
    const double ri = p.radius[i];
    Vec3 forceI = Vec3::Zero();
    Vec3 torqueI = Vec3::Zero();
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const std::uint32_t j = partners[k];
      const Vec3 d = p.position[j] - xi;
      const double radiusSum = ri + p.radius[j];
      const double dist2 = d.squaredNorm();
      if (dist2 >= radiusSum * radiusSum) {
        if (!history[k].isZero(0.0)) history[k].setZero();  // no store traffic for idle pairs
        continue;
      }
      const double dist = std::sqrt(dist2);
      // Coincident centres have no defined normal: push along +z rather than produce NaN.
      // (One reciprocal: Eigen's d / dist would issue three divisions.)
      const Vec3 normal = dist > 0.0 ? Vec3(d * (1.0 / dist)) : Vec3::UnitZ();
      const double overlap = radiusSum - dist;
      const double armI = ri - 0.5 * overlap;
      const double armJ = p.radius[j] - 0.5 * overlap;
      const Vec3 vRel =
          p.velocity[j] - p.velocity[i] - (armI * p.angular_velocity[i] + armJ * p.angular_velocity[j]).cross(normal);
      const double rStar = reduced[k].radius;
      const double mStar = reduced[k].mass;
      const ContactPairParams& params = table(p.material[i], p.material[j]);
      double normalForce = 0.0;
      const Vec3 f = contactForce<Law>(params, normal, overlap, vRel, rStar, mStar, dt, history[k], normalForce);
      const Vec3 nxf = normal.cross(f);
      forceI -= f;
      torqueI -= armI * nxf;
      force[j - base] += f;
      torque[j - base] -= armJ * nxf;
      if constexpr (kRolling) {
        if (params.rolling_friction > 0.0) {
          const double reducedInertia = 1.0 / (p.inv_inertia[i] + p.inv_inertia[j]);
          const Vec3 t = rollingResistanceTorque(params.rolling_friction, rStar, normalForce, normal,
                                                 p.angular_velocity[j] - p.angular_velocity[i], reducedInertia, dt);
          torque[j - base] += t;
          torqueI -= t;
        }
      }
    }
    force[i - base] += forceI;
    torque[i - base] += torqueI;
  }
}

/// Contact of particle `slot` with a rigid wall surface at `contactPoint` whose
/// unit normal points to the particle; wallVelocity is the wall's velocity at the
/// contact point. Returns the force on the particle; adds force and torque to it.
template <class Law, bool kRolling>
DEMLINK_FORCE_INLINE Vec3 particleWallContact(ParticleArrays& p, std::size_t slot, const ContactPairParams& params,
                                const Vec3& normal, double overlap, const Vec3& wallVelocity, double dt,
                                typename Law::History& history) {
  // A rigid wall does not deform: the contact point is on its surface.
  const double arm = p.radius[slot] - overlap;
  const Vec3 vRel = p.velocity[slot] - arm * p.angular_velocity[slot].cross(normal) - wallVelocity;
  const double rStar = p.radius[slot];
  // The body's mass: for a clump member inv_mass is 1 / clump mass (mass is its share).
  const double mStar = 1.0 / p.inv_mass[slot];
  double normalForce = 0.0;
  const Vec3 f = contactForce<Law>(params, normal, overlap, vRel, rStar, mStar, dt, history, normalForce);
  p.force[slot] += f;
  p.torque[slot] -= arm * normal.cross(f);
  if constexpr (kRolling) {
    if (params.rolling_friction > 0.0) {
      p.torque[slot] += rollingResistanceTorque(params.rolling_friction, rStar, normalForce, normal,
                                                p.angular_velocity[slot], 1.0 / p.inv_inertia[slot], dt);
    }
  }
  return f;
}

template <class Law, bool kRolling>
void planeContactForces(ParticleArrays& p, PlaneWall& wall, const ContactPairTable& table, double dt) {
  static_assert(kHistoryStorageFits<Law, decltype(wall.near_history)>, "plane near history is not Law::History");
  const Vec3 normal = wall.spec.normal;
  for (std::size_t k = 0; k < wall.near_slots.size(); ++k) {
    const std::uint32_t slot = wall.near_slots[k];
    const double distance = (p.position[slot] - wall.spec.point).dot(normal);
    const double overlap = p.radius[slot] - distance;
    if (overlap <= 0.0) {
      wall.near_history[k].setZero();
      continue;
    }
    const Vec3 f = particleWallContact<Law, kRolling>(p, slot, table(p.material[slot], wall.spec.material), normal,
                                                      overlap, Vec3::Zero(), dt, wall.near_history[k]);
    const Vec3 contactPoint = p.position[slot] - distance * normal;
    wall.force -= f;
    wall.torque -= (contactPoint - wall.spec.point).cross(f);
  }
}

/// Particle-surface contacts: a mesh (MeshBody) or a deformable body's surface
/// (DeformableSurface); both give worldVertices(), triangles(), materialIndex(),
/// velocityAt(triangle, point) and addContactForce(triangle, point, force). Per
/// particle, the de-duplicated contacts with its candidate triangles
/// (mesh_contact.hpp) each get the wall contact law with the surface's velocity at
/// the contact point. Each candidate keeps its own tangential spring; when a
/// particle rolls from one triangle onto the next, the spring of the triangle it
/// left is handed to the new contact instead of being dropped, so a finely meshed
/// flat floor behaves like a plane.
template <class Law, bool kRolling, class Surface>
void meshContactForces(ParticleArrays& p, Surface& mesh, MeshNearList& near, const ContactPairTable& table,
                       double dt, std::vector<MeshContactPoint>& contacts) {
  static_assert(kHistoryStorageFits<Law, decltype(near.history)>, "mesh near history is not Law::History");
  const std::span<const Vec3> vertices = mesh.worldVertices();
  const std::span<const std::array<std::uint32_t, 3>> triangles = mesh.triangles();
  for (std::size_t k = 0; k < near.slots.size(); ++k) {
    const std::uint32_t slot = near.slots[k];
    const std::uint32_t rowBegin = near.offsets[k];
    const std::uint32_t rowEnd = near.offsets[k + 1];
    contacts.clear();
    collectSphereMeshContacts(p.position[slot], p.radius[slot],
                              std::span<const std::uint32_t>(near.triangles.data() + rowBegin, rowEnd - rowBegin),
                              vertices, triangles, contacts);
    auto entryOf = [&](std::uint32_t triangle) {
      return static_cast<std::uint32_t>(
          std::lower_bound(near.triangles.begin() + rowBegin, near.triangles.begin() + rowEnd, triangle) -
          near.triangles.begin());
    };
    // Springs of candidates that touched last step but not now are released ...
    std::uint32_t released[4];
    std::uint32_t releasedCount = 0;
    for (std::uint32_t e = rowBegin; e < rowEnd; ++e) {
      if (near.history[e].isZero(0.0)) continue;
      const bool touching = std::any_of(contacts.begin(), contacts.end(),
                                        [&](const MeshContactPoint& c) { return c.triangle == near.triangles[e]; });
      if (touching) continue;
      if (releasedCount < 4) released[releasedCount++] = e; else near.history[e].setZero();
    }
    const ContactPairParams& params = table(p.material[slot], mesh.materialIndex());
    for (const MeshContactPoint& c : contacts) {
      typename Law::History& history = near.history[entryOf(c.triangle)];
      // ... and handed to a new contact of the same particle.
      if (history.isZero(0.0) && releasedCount > 0) {
        const std::uint32_t from = released[--releasedCount];
        history = near.history[from];
        near.history[from].setZero();
      }
      const Vec3 f = particleWallContact<Law, kRolling>(p, slot, params, c.normal, c.overlap,
                                                        mesh.velocityAt(c.triangle, c.point), dt, history);
      mesh.addContactForce(c.triangle, c.point, -f);
    }
    for (std::uint32_t r = 0; r < releasedCount; ++r) near.history[released[r]].setZero();
  }
}

}  // namespace demlink::core
