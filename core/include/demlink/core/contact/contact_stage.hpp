#pragma once
/// Force stage loops: particle-particle (over the half neighbour list),
/// particle-plane (over each plane's near list) and particle-surface (over the
/// near list of each mesh or deformable body's surface). Templated on the contact law
/// and on the optional passes (rolling resistance, cohesion, contact recording), so
/// the compiled loop contains exactly what the scene uses; the world picks one
/// instantiation at set-up (contact_law_registry.hpp). Each loop checks that the
/// per-contact history its storage keeps is the one the law declares.
#include <algorithm>
#include <array>
#include <cstdint>
#include <numbers>
#include <ranges>
#include <type_traits>

#include "demlink/core/contact/contact_kernel.hpp"
#include "demlink/core/contact/contact_pair_table.hpp"
#include "demlink/core/contact/contact_record.hpp"
#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/walls/mesh_contact.hpp"
#include "demlink/core/walls/mesh_near_list.hpp"
#include "demlink/core/particles/neighbour_list.hpp"
#include "demlink/core/particles/particle_arrays.hpp"
#include "demlink/core/step/pair_loop_partition.hpp"
#include "demlink/core/walls/plane_wall.hpp"

namespace demlink::core {

/// True when `Storage` (a near list's history column) holds Law::History per entry.
template <class Law, class Storage>
inline constexpr bool kHistoryStorageFits =
    std::is_same_v<typename Law::History, std::ranges::range_value_t<std::remove_cvref_t<Storage>>>;

/// Contact area A = pi a^2 [m^2] of an overlap, for the cohesive attraction k_c A [N].
/// Two spheres of radii r1, r2 at centre distance d (overlap delta = r1 + r2 - d)
/// meet in a circle of radius
///   a^2 = delta (d + r1 + r2) (d^2 - (r1 - r2)^2) / (4 d^2),
/// the product form of the sphere-sphere intersection (no cancellation at small
/// delta; a^2 -> 2 R* delta as delta -> 0, R* = r1 r2 / (r1 + r2)). A sphere on a
/// wall: a^2 = delta (2 r - delta), the limit r2 -> infinity. Clamped at a^2 >= 0
/// (one sphere inside the other).
DEMLINK_FORCE_INLINE double pairContactArea(double r1, double r2, double distance, double overlap) {
  const double dr = r1 - r2;
  const double a2 = overlap * (distance + r1 + r2) * (distance * distance - dr * dr) / (4.0 * distance * distance);
  return std::numbers::pi * std::max(a2, 0.0);
}
DEMLINK_FORCE_INLINE double wallContactArea(double radius, double overlap) {
  return std::numbers::pi * std::max(overlap * (2.0 * radius - overlap), 0.0);
}

/// Potential of the cohesive force at `overlap`: U = -k_c * integral_0^overlap A [J], so a
/// cohesive contact's elastic plus cohesive energy is conserved without damping. rB = 0: a
/// wall (A quadratic in the overlap, integrated exactly); pairs by Simpson's rule, whose
/// relative error is of order (overlap / r)^4.
inline double cohesionEnergy(double kc, double rA, double rB, double overlap) {
  if (kc == 0.0 || overlap <= 0.0) return 0.0;
  if (rB <= 0.0) return -kc * std::numbers::pi * overlap * overlap * (rA - overlap / 3.0);
  auto area = [&](double delta) { return pairContactArea(rA, rB, rA + rB - delta, delta); };
  return -kc * overlap / 6.0 * (4.0 * area(0.5 * overlap) + area(overlap));
}

/// Velocity of a particle's contact point on a rigid wall relative to the wall.
DEMLINK_FORCE_INLINE Vec3 wallContactVelocity(const ParticleArrays& p, std::size_t slot, const Vec3& normal,
                                              double overlap, const Vec3& wallVelocity) {
  // A rigid wall does not deform: the contact point is on its surface.
  const double arm = p.radius[slot] - overlap;
  return p.velocity[slot] - arm * p.angular_velocity[slot].cross(normal) - wallVelocity;
}

/// A contact record of particle `slot` (body a) with `other`, the force on a being `force`.
inline ContactRecord makeContactRecord(ContactKind kind, const ParticleArrays& p, std::size_t slot,
                                       std::uint64_t other, std::uint32_t triangle, const Vec3& otherPoint,
                                       const Vec3& contactPoint, const Vec3& normal, double overlap,
                                       const Vec3& force) {
  ContactRecord r;
  r.kind = kind;
  r.particle = p.id[slot];
  r.other = other;
  r.triangle = triangle;
  r.centre = p.position[slot];
  r.other_point = otherPoint;
  r.contact_point = contactPoint;
  r.normal = normal;
  r.overlap = overlap;
  r.normal_force = force.dot(normal) * normal;
  r.tangential_force = force - r.normal_force;
  return r;
}

/// Particle-particle contacts of rows [rowBegin, rowEnd) of the half list.
/// Forces and torques are added into `out` (PairLoopPartition says which chunks may run
/// at the same time). With
/// kPasses.recording and `records` set, each contact is appended to *records.
///
/// The rows' pairs are walked as one sequence (NeighbourList::rows() names each
/// pair's row) in blocks of listed pairs, not row by row: a settled bed lists ~4
/// pairs per row, and loops that short mispredict their exit once per row. A first
/// pass sorts a block's pairs into touching and just separated without a branch on
/// the answer (about half the listed pairs of a settled bed do not touch, in no
/// pattern a branch predictor can learn), keeping NeighbourList::sprung() up to date;
/// then the separated ones release their springs and the touching ones are evaluated
/// in list order, their overlap-only terms first. Pairs that stay apart never load
/// their history.
///
/// The body is compiled into two loops (pair_kernel.hpp): particleContactRows, portable,
/// and particleContactRowsAvx2Fma for processors with AVX2 and FMA.
template <class Law, ForcePasses kPasses>
DEMLINK_FORCE_INLINE void particleContactRowsBody(ParticleArrays& p, NeighbourList& list,
                                                  const ContactPairTable& table, double dt, std::size_t rowBegin,
                                                  std::size_t rowEnd, const ChunkForces& out,
                                                  std::vector<ContactRecord>* records) {
  const std::span<const std::uint32_t> offsets = list.offsets();
  const std::span<const std::uint32_t> partners = list.partners();
  const std::span<const std::uint32_t> rows = list.rows();
  const std::span<Vec3> history = list.history();
  static_assert(kHistoryStorageFits<Law, decltype(list.history())>, "neighbour list history is not Law::History");
  const std::span<const ReducedPair> reduced = list.reduced();
  const std::span<std::uint8_t> sprung = list.sprung();
  constexpr std::uint32_t kBlock = 64;
  std::uint32_t touching[kBlock];
  std::uint32_t separated[kBlock];
  // Per touching contact of a block: its unit normal (i to j; the centre offset until
  // normalised), distance, overlap and elastic terms.
  Vec3 normals[kBlock];
  double squaredDistances[kBlock];
  double radiiSums[kBlock];
  double distances[kBlock];
  double overlaps[kBlock];
  double inverseDistances[kBlock];
  const ContactPairParams* pairParams[kBlock];
  ContactElasticTerms elastic[kBlock];
  // Per touching contact: the force on j, its normal force, the lever arms of i and j, and
  // (with rolling resistance) the rolling torque on j.
  Vec3 forces[kBlock];
  double normalForces[kBlock];
  std::array<double, 2> arms[kBlock];
  [[maybe_unused]] Vec3 rollingTorques[kPasses.rolling ? kBlock : 1];
  const std::uint32_t pairEnd = offsets[rowEnd];
  for (std::uint32_t blockBegin = offsets[rowBegin]; blockBegin < pairEnd; blockBegin += kBlock) {
    const std::uint32_t blockEnd = std::min(pairEnd, blockBegin + kBlock);
    std::uint32_t count = 0;
    std::uint32_t separatedCount = 0;
    for (std::uint32_t k = blockBegin; k < blockEnd; ++k) {
      const std::uint32_t i = rows[k];
      const std::uint32_t j = partners[k];
      const double radiusSum = p.radius[i] + p.radius[j];
      const auto touches =
          static_cast<std::uint8_t>(!((p.position[j] - p.position[i]).squaredNorm() >= radiusSum * radiusSum));
      const std::uint8_t had = sprung[k];
      sprung[k] = touches;
      // Both stores always, so no branch.
      touching[count] = k;
      separated[separatedCount] = k;
      count += touches;
      separatedCount += static_cast<std::uint32_t>(had & (touches ^ 1u));
    }
    // Springs of pairs that came apart are released (and only if set: no store for a
    // spring that never built up).
    for (std::uint32_t m = 0; m < separatedCount; ++m) {
      if (!history[separated[m]].isZero(0.0)) history[separated[m]].setZero();
    }
    // The overlap-only terms of the touching pairs first (contactElasticTerms says why),
    // in passes over arrays so the compiler can take two contacts at a time (sqrtpd,
    // divpd): gather, then distance and overlap, then the law's terms.
    for (std::uint32_t m = 0; m < count; ++m) {
      const std::uint32_t k = touching[m];
      const std::uint32_t i = rows[k];
      const std::uint32_t j = partners[k];
      normals[m] = p.position[j] - p.position[i];
      squaredDistances[m] = normals[m].squaredNorm();
      radiiSums[m] = p.radius[i] + p.radius[j];
      pairParams[m] = &table(p.material[i], p.material[j]);
    }
    for (std::uint32_t m = 0; m < count; ++m) {
      const double dist = std::sqrt(squaredDistances[m]);
      distances[m] = dist;
      overlaps[m] = radiiSums[m] - dist;
      inverseDistances[m] = 1.0 / dist;
    }
    for (std::uint32_t m = 0; m < count; ++m) {
      const std::uint32_t k = touching[m];
      // Coincident centres have no defined normal: push along +z rather than produce NaN.
      normals[m] = distances[m] > 0.0 ? Vec3(normals[m] * inverseDistances[m]) : Vec3::UnitZ();
      elastic[m] = contactElasticTerms<Law>(*pairParams[m], reduced[k].radius, reduced[k].mass, overlaps[m]);
    }
    // The forces of the touching pairs, then (with rolling resistance) their rolling
    // torques in a pass of their own: each ends in a chain of a square root and three
    // divisions, which, one contact at a time, stalled the loop; over an array the
    // processor overlaps the chains of several contacts. Then every sum in list order,
    // as one pass would add them.
    for (std::uint32_t m = 0; m < count; ++m) {
      const std::uint32_t k = touching[m];
      const std::uint32_t i = rows[k];
      const std::uint32_t j = partners[k];
      const Vec3& normal = normals[m];
      const double overlap = overlaps[m];
      const double ri = p.radius[i];
      const double armI = ri - 0.5 * overlap;
      const double armJ = p.radius[j] - 0.5 * overlap;
      const Vec3 vRel = p.velocity[j] - p.velocity[i] -
                        (armI * p.angular_velocity[i] + armJ * p.angular_velocity[j]).cross(normal);
      const ContactPairParams& params = *pairParams[m];
      double normalForce = 0.0;
      Vec3 f = contactForce<Law>(params, normal, elastic[m], vRel, dt, history[k], normalForce);
      if constexpr (kPasses.cohesion) {
        // Pulls j back towards i; the friction cap (above) and rolling resistance (below) see the
        // repulsive part alone.
        f -= (params.cohesion_energy_density * pairContactArea(ri, p.radius[j], distances[m], overlap)) * normal;
      }
      if constexpr (kPasses.recording) {
        if (records != nullptr) {
          records->push_back(makeContactRecord(ContactKind::kParticle, p, i, p.id[j], 0, p.position[j],
                                               p.position[i] + armI * normal, -normal, overlap, -f));
        }
      }
      forces[m] = f;
      normalForces[m] = normalForce;
      arms[m] = {armI, armJ};
    }
    if constexpr (kPasses.rolling) {
      for (std::uint32_t m = 0; m < count; ++m) {
        const ContactPairParams& params = *pairParams[m];
        if (!(params.rolling_friction > 0.0)) continue;
        const std::uint32_t k = touching[m];
        const std::uint32_t i = rows[k];
        const std::uint32_t j = partners[k];
        rollingTorques[m] = rollingResistanceTorque(params.rolling_friction, reduced[k].radius, normalForces[m],
                                                    normals[m], p.angular_velocity[j] - p.angular_velocity[i],
                                                    p.inv_inertia[i] + p.inv_inertia[j], dt);
      }
    }
    for (std::uint32_t m = 0; m < count; ++m) {
      const std::uint32_t k = touching[m];
      const std::uint32_t i = rows[k];
      const std::uint32_t j = partners[k];
      const Vec3& f = forces[m];
      const auto [armI, armJ] = arms[m];
      const Vec3 nxf = normals[m].cross(f);
      out.force[i] -= f;
      out.torque[i] -= armI * nxf;
      out.force[j] += f;
      Vec3& torqueJ = out.torque[j];
      torqueJ -= armJ * nxf;
      if constexpr (kPasses.rolling) {
        if (pairParams[m]->rolling_friction > 0.0) {
          const Vec3& t = rollingTorques[m];
          torqueJ += t;
          out.torque[i] -= t;
        }
      }
    }
  }
}

template <class Law, ForcePasses kPasses>
void particleContactRows(ParticleArrays& p, NeighbourList& list, const ContactPairTable& table, double dt,
                         std::size_t rowBegin, std::size_t rowEnd, const ChunkForces& out,
                         std::vector<ContactRecord>* records = nullptr) {
  particleContactRowsBody<Law, kPasses>(p, list, table, dt, rowBegin, rowEnd, out, records);
}

#if defined(__x86_64__) && defined(__GNUC__)
#define DEMLINK_AVX2_FMA_PAIR_KERNEL 1
/// The same loop for processors with AVX2 and FMA (only call it on one: choosePairKernel).
/// Aligned to a cache line: where its loops fall relative to 32-byte boundaries moved with
/// unrelated code in world.cpp and changed the forces stage by up to 7 % (5,000 spheres).
template <class Law, ForcePasses kPasses>
__attribute__((target("avx2,fma"), aligned(64))) void particleContactRowsAvx2Fma(
    ParticleArrays& p, NeighbourList& list, const ContactPairTable& table, double dt, std::size_t rowBegin,
    std::size_t rowEnd, const ChunkForces& out, std::vector<ContactRecord>* records = nullptr) {
  particleContactRowsBody<Law, kPasses>(p, list, table, dt, rowBegin, rowEnd, out, records);
}
#else
#define DEMLINK_AVX2_FMA_PAIR_KERNEL 0
template <class Law, ForcePasses kPasses>
void particleContactRowsAvx2Fma(ParticleArrays& p, NeighbourList& list, const ContactPairTable& table, double dt,
                                std::size_t rowBegin, std::size_t rowEnd, const ChunkForces& out,
                                std::vector<ContactRecord>* records = nullptr) {
  particleContactRows<Law, kPasses>(p, list, table, dt, rowBegin, rowEnd, out, records);
}
#endif

/// Contact of particle `slot` with a rigid wall surface at `contactPoint` whose
/// unit normal points to the particle; wallVelocity is the wall's velocity at the
/// contact point. Returns the force on the particle; adds force and torque to it.
/// `vRel` is wallContactVelocity(p, slot, normal, overlap, wallVelocity).
template <class Law, ForcePasses kPasses>
DEMLINK_FORCE_INLINE Vec3 particleWallContact(ParticleArrays& p, std::size_t slot, const ContactPairParams& params,
                                const Vec3& normal, double overlap, const Vec3& vRel, double dt,
                                typename Law::History& history) {
  const double arm = p.radius[slot] - overlap;
  const double rStar = p.radius[slot];
  // The body's mass: for a clump member inv_mass is 1 / clump mass (mass is its share).
  const double mStar = 1.0 / p.inv_mass[slot];
  double normalForce = 0.0;
  Vec3 f = contactForce<Law>(params, normal, overlap, vRel, rStar, mStar, dt, history, normalForce);
  if constexpr (kPasses.cohesion) {
    f -= (params.cohesion_energy_density * wallContactArea(p.radius[slot], overlap)) * normal;
  }
  p.force[slot] += f;
  p.torque[slot] -= arm * normal.cross(f);
  if constexpr (kPasses.rolling) {
    if (params.rolling_friction > 0.0) {
      p.torque[slot] += rollingResistanceTorque(params.rolling_friction, rStar, normalForce, normal,
                                                p.angular_velocity[slot], p.inv_inertia[slot], dt);
    }
  }
  return f;
}

/// A contact of particle `slot` with a wall (b): appends its record and adds it to
/// its triangle's load, as far as `recording` asks.
inline void recordWallContact(const ParticleArrays& p, std::size_t slot, const ContactRecording& recording,
                              std::uint32_t triangle, const Vec3& point, const Vec3& normal, double overlap,
                              const Vec3& force, const Vec3& vRel) {
  if (recording.contacts != nullptr) {
    recording.contacts->push_back(
        makeContactRecord(recording.kind, p, slot, recording.index, triangle, point, point, normal, overlap, force));
  }
  if (recording.loads == nullptr) return;
  TriangleLoad& load = (*recording.loads)[triangle];
  const double fn = force.dot(normal);
  const double ft = (force - fn * normal).norm();
  const double slip = (vRel - vRel.dot(normal) * normal).norm();
  load.force -= force;
  load.normal_force += fn;
  load.tangential_force += ft;
  load.normal_impulse += fn * recording.dt;
  load.tangential_impulse += ft * recording.dt;
  load.archard_work += std::max(fn, 0.0) * slip * recording.dt;
  load.friction_work += ft * slip * recording.dt;
}

/// The contacts of `wall` with the near-list entries whose slots lie in [slotBegin,
/// slotEnd) (the list is ascending): added to the particles; returns what they add to the
/// wall. Stretches of disjoint slots touch disjoint particles, so they may run at once.
template <class Law, ForcePasses kPasses>
PlaneLoad planeContactSlots(ParticleArrays& p, PlaneWall& wall, const ContactPairTable& table, double dt,
                            std::size_t slotBegin, std::size_t slotEnd, const ContactRecording& recording = {}) {
  static_assert(kHistoryStorageFits<Law, decltype(wall.near_history)>, "plane near history is not Law::History");
  const Vec3 normal = wall.spec.normal;
  const auto first = std::lower_bound(wall.near_slots.begin(), wall.near_slots.end(), slotBegin);
  const auto last = std::lower_bound(first, wall.near_slots.end(), slotEnd);
  PlaneLoad load;
  for (auto k = static_cast<std::size_t>(first - wall.near_slots.begin());
       k < static_cast<std::size_t>(last - wall.near_slots.begin()); ++k) {
    const std::uint32_t slot = wall.near_slots[k];
    const double distance = (p.position[slot] - wall.spec.point).dot(normal);
    const double overlap = p.radius[slot] - distance;
    if (overlap <= 0.0) {
      wall.near_history[k].setZero();
      continue;
    }
    const Vec3 vRel = wallContactVelocity(p, slot, normal, overlap, Vec3::Zero());
    const Vec3 f = particleWallContact<Law, kPasses>(p, slot, table(p.material[slot], wall.spec.material), normal,
                                                     overlap, vRel, dt, wall.near_history[k]);
    const Vec3 contactPoint = p.position[slot] - distance * normal;
    if constexpr (kPasses.recording) recordWallContact(p, slot, recording, 0, contactPoint, normal, overlap, f, vRel);
    load.force -= f;
    load.torque -= (contactPoint - wall.spec.point).cross(f);
  }
  return load;
}

/// Particle-surface contacts of the near-list entries [entryBegin, entryEnd) of a mesh
/// (MeshBody) or a deformable body's surface (DeformableSurface); both give
/// worldVertices(), triangles(), materialIndex(), velocityAt(triangle, point) and
/// addContactForce(triangle, point, force). Per particle, the de-duplicated contacts with
/// its candidate triangles (mesh_contact.hpp) each get the wall contact law with the
/// surface's velocity at the contact point; the force on the surface goes to
/// onSurface(triangle, point, force), in entry order. Each candidate keeps its own
/// tangential spring; when a particle rolls from one triangle onto the next, the spring of
/// the triangle it left is handed to the new contact instead of being dropped, so a finely
/// meshed flat floor behaves like a plane. Entries are distinct particles, so disjoint
/// stretches of entries may run at once (they read the surface, never write it).
template <class Law, ForcePasses kPasses, class Surface, class OnSurface>
void meshContactEntries(ParticleArrays& p, const Surface& mesh, MeshNearList& near, const ContactPairTable& table,
                        double dt, std::size_t entryBegin, std::size_t entryEnd,
                        std::vector<MeshContactPoint>& contacts, const ContactRecording& recording,
                        OnSurface&& onSurface) {
  static_assert(kHistoryStorageFits<Law, decltype(near.history)>, "mesh near history is not Law::History");
  const std::span<const Vec3> vertices = mesh.worldVertices();
  const std::span<const std::array<std::uint32_t, 3>> triangles = mesh.triangles();
  for (std::size_t k = entryBegin; k < entryEnd; ++k) {
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
      const Vec3 vRel = wallContactVelocity(p, slot, c.normal, c.overlap, mesh.velocityAt(c.triangle, c.point));
      const Vec3 f = particleWallContact<Law, kPasses>(p, slot, params, c.normal, c.overlap, vRel, dt, history);
      onSurface(c.triangle, c.point, Vec3(-f));
      if constexpr (kPasses.recording) {
        recordWallContact(p, slot, recording, c.triangle, c.point, c.normal, c.overlap, f, vRel);
      }
    }
    for (std::uint32_t r = 0; r < releasedCount; ++r) near.history[released[r]].setZero();
  }
}

/// All the contacts of a surface's near list, in entry order, on the calling thread.
template <class Law, ForcePasses kPasses, class Surface>
void meshContactForces(ParticleArrays& p, Surface& mesh, MeshNearList& near, const ContactPairTable& table,
                       double dt, std::vector<MeshContactPoint>& contacts, const ContactRecording& recording = {}) {
  meshContactEntries<Law, kPasses>(
      p, mesh, near, table, dt, 0, near.slots.size(), contacts, recording,
      [&mesh](std::uint32_t triangle, const Vec3& point, const Vec3& force) { mesh.addContactForce(triangle, point, force); });
}

/// The contacts of a surface's near-list entries whose slots lie in [slotBegin, slotEnd)
/// (the list is ascending in slot): added to the particles, the forces on the surface kept
/// in `part`, in list order (addSurfaceLoads adds them). Disjoint stretches of slots touch
/// disjoint particles and only read the surface, so they may run at once; the force stage
/// runs each pair-loop chunk's own rows, beside its planes.
template <class Law, ForcePasses kPasses, class Surface>
void meshContactSlots(ParticleArrays& p, const Surface& mesh, MeshNearList& near, const ContactPairTable& table,
                      double dt, std::size_t slotBegin, std::size_t slotEnd, MeshContactChunk& part) {
  static_assert(!kPasses.recording, "recorded contacts keep list order: run meshContactForces");
  const auto first = std::lower_bound(near.slots.begin(), near.slots.end(), slotBegin);
  const auto last = std::lower_bound(first, near.slots.end(), slotEnd);
  meshContactEntries<Law, kPasses>(p, mesh, near, table, dt, static_cast<std::size_t>(first - near.slots.begin()),
                                   static_cast<std::size_t>(last - near.slots.begin()), part.contacts, {},
                                   [&part](std::uint32_t triangle, const Vec3& point, const Vec3& force) {
                                     part.loads.push_back({triangle, point, force});
                                   });
}

/// Adds what meshContactSlots kept to the surface.
template <class Surface>
void addSurfaceLoads(Surface& mesh, const MeshContactChunk& part) {
  for (const MeshContactChunk::SurfaceLoad& load : part.loads) mesh.addContactForce(load.triangle, load.point, load.force);
}

}  // namespace demlink::core
