/// A world's parallel bonds (contract in bond_set.hpp).
#include "demlink/core/bonds/bond_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <spdlog/fmt/fmt.h>
#include <unordered_map>
#include <utility>

#include "demlink/core/base/random.hpp"
#include "demlink/core/contact/critical_time_step.hpp"
#include "demlink/core/materials/material.hpp"
#include "demlink/core/parallel/parallel_loops.hpp"
#include "demlink/core/particles/sphere.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/walls/mesh_body.hpp"

namespace demlink::core {

/// A hash grid of cells 2 max R + gap wide: every such pair lies in the same or an
/// adjacent cell.
std::vector<std::pair<std::uint32_t, std::uint32_t>> pairsWithinGap(const ParticleArrays& p,
                                                                    const std::vector<char>& eligible, double gap) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  double largest = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (eligible[i] != 0) largest = std::max(largest, p.radius[i]);
  }
  if (largest <= 0.0) return pairs;
  const double cell = 2.0 * largest + gap;
  const auto keyOf = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    // 21 bits a coordinate: cells within +-1e6 of the origin are distinct.
    return (static_cast<std::uint64_t>(x & 0x1FFFFF) << 42) | (static_cast<std::uint64_t>(y & 0x1FFFFF) << 21) |
           static_cast<std::uint64_t>(z & 0x1FFFFF);
  };
  const auto cellOf = [&](const Vec3& x) {
    return Eigen::Vector3<std::int64_t>(static_cast<std::int64_t>(std::floor(x.x() / cell)),
                                        static_cast<std::int64_t>(std::floor(x.y() / cell)),
                                        static_cast<std::int64_t>(std::floor(x.z() / cell)));
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    if (eligible[i] == 0) continue;
    const auto c = cellOf(p.position[i]);
    grid[keyOf(c.x(), c.y(), c.z())].push_back(i);
  }
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    if (eligible[i] == 0) continue;
    const auto c = cellOf(p.position[i]);
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(keyOf(c.x() + dx, c.y() + dy, c.z() + dz));
          if (it == grid.end()) continue;
          for (const std::uint32_t j : it->second) {
            if (p.id[j] <= p.id[i]) continue;
            if (p.clump_id[i] != 0 && p.clump_id[i] == p.clump_id[j]) continue;
            const double reach = p.radius[i] + p.radius[j] + gap;
            if ((p.position[j] - p.position[i]).squaredNorm() <= reach * reach) pairs.emplace_back(i, j);
          }
        }
      }
    }
  }
  std::sort(pairs.begin(), pairs.end(), [&](const auto& a, const auto& b) {
    return std::pair(p.id[a.first], p.id[a.second]) < std::pair(p.id[b.first], p.id[b.second]);
  });
  return pairs;
}

std::size_t BondSet::addRule(BondRule rule) {
  rules_.push_back(std::move(rule));
  made_.push_back(0);
  return rules_.size() - 1;
}

BondSection BondSet::section(const ParallelBond& bond, const ParticleArrays& particles) const {
  return BondSection::of(rules_[bond.rule].properties.radius_multiplier, particles.radius[bond.slot_a],
                         particles.radius[bond.slot_b]);
}

namespace {
// What became of a bond in one step (BondSet::step's outcomes_).
constexpr std::uint8_t kBondSkipped = 0;  // broken before the step
constexpr std::uint8_t kBondLoaded = 1;   // intact: its load is to be added
constexpr std::uint8_t kBondBroke = 2;    // broke in this step
}  // namespace

void BondSet::step(ThreadPool* pool, const std::vector<MeshBody>& meshes, double time, ParticleArrays& p, double dt,
                   std::uint64_t stepCount) {
  const std::size_t n = bonds_.size();
  loads_.resize(n);
  outcomes_.resize(n);
  // A bond reads its particles and writes only itself, its load and its outcome. Bonds
  // are in creation order, their particles anywhere in the slots, so reading them misses
  // the cache: the particles of the bond kPrefetchAhead on are fetched while this one is
  // computed.
  constexpr std::size_t kPrefetchAhead = 8;
  parallelChunks(pool, n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      if (k + kPrefetchAhead < end) {
        for (const std::uint32_t slot : {bonds_[k + kPrefetchAhead].slot_a, bonds_[k + kPrefetchAhead].slot_b}) {
          __builtin_prefetch(&p.position[slot]);
          __builtin_prefetch(&p.velocity[slot]);
          __builtin_prefetch(&p.angular_velocity[slot]);
          __builtin_prefetch(&p.radius[slot]);
        }
      }
      ParallelBond& bond = bonds_[k];
      if (bond.broken) {
        outcomes_[k] = kBondSkipped;
        continue;
      }
      const std::uint32_t a = bond.slot_a;
      const std::uint32_t b = bond.slot_b;
      const BondEnds ends{p.position[a], p.position[b], p.velocity[a],     p.velocity[b],
                          p.angular_velocity[a], p.angular_velocity[b], p.radius[a], p.radius[b]};
      loads_[k] = advanceParallelBond(bond, rules_[bond.rule].properties, ends, dt);
      outcomes_[k] = bond.broken ? kBondBroke : kBondLoaded;
    }
  });
  // Particles share bonds: their sums are added here, in bond order.
  for (std::size_t k = 0; k < n; ++k) {
    if (outcomes_[k] == kBondSkipped) continue;
    if (outcomes_[k] == kBondBroke) {
      --counts_.intact;
      ++counts_.broken;
      continue;
    }
    const ParallelBond& bond = bonds_[k];
    const BondLoad& load = loads_[k];
    p.force[bond.slot_a] += load.force_a;
    p.force[bond.slot_b] -= load.force_a;
    p.torque[bond.slot_a] += load.torque_a;
    p.torque[bond.slot_b] += load.torque_b;
  }
  for (std::size_t r = 0; r < rules_.size(); ++r) {
    if (made_[r] == 0 && stepCount >= rules_[r].create_step) make(meshes, time, p, r);
  }
}

void BondSet::make(const std::vector<MeshBody>& meshes, double time, const ParticleArrays& p,
                   std::size_t ruleIndex) {
  made_[ruleIndex] = 1;
  const BondRule& rule = rules_[ruleIndex];
  std::vector<char> eligible(p.size(), 1);
  const RegionPose pose = rule.region ? rule.placement.poseAt(meshes, time) : RegionPose{};
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (rule.groups && !rule.groups->contains(p.id[i])) {
      eligible[i] = 0;
    } else if (!rule.materials.empty() &&
        std::find(rule.materials.begin(), rule.materials.end(), p.material[i]) == rule.materials.end()) {
      eligible[i] = 0;
    } else if (rule.region && !rule.region->contains(pose, p.position[i])) {
      eligible[i] = 0;
    }
  }
  std::set<std::pair<std::uint64_t, std::uint64_t>> existing;
  for (const ParallelBond& bond : bonds_) existing.emplace(bond.id_a, bond.id_b);
  Random random(rule.seed);
  for (const auto& [a, b] : pairsWithinGap(p, eligible, rule.properties.gap_tolerance)) {
    if (rule.groups && rule.groups->at(p.id[a]) != rule.groups->at(p.id[b])) continue;
    if (rule.fraction < 1.0 && !(random.uniform() < rule.fraction)) continue;
    if (existing.contains({p.id[a], p.id[b]})) continue;
    ParallelBond bond;
    bond.id_a = p.id[a];
    bond.id_b = p.id[b];
    bond.slot_a = a;
    bond.slot_b = b;
    bond.rule = static_cast<std::uint32_t>(ruleIndex);
    bond.normal = (p.position[b] - p.position[a]).normalized();
    bonds_.push_back(bond);
    ++counts_.intact;
  }
}

void BondSet::remapSlots(std::span<const std::uint32_t> newSlotOfOld) {
  std::size_t kept = 0;
  for (ParallelBond& bond : bonds_) {
    const std::uint32_t a = newSlotOfOld[bond.slot_a];
    const std::uint32_t b = newSlotOfOld[bond.slot_b];
    if (a == kRemovedSlot || b == kRemovedSlot) {
      if (!bond.broken) {
        --counts_.intact;
        ++counts_.dropped;
      }
      continue;
    }
    bond.slot_a = a;
    bond.slot_b = b;
    bonds_[kept++] = bond;
  }
  bonds_.resize(kept);
}

double BondSet::strainEnergy(const ParticleArrays& particles) const {
  double energy = 0.0;
  for (const ParallelBond& bond : bonds_) {
    if (!bond.broken) energy += bondStrainEnergy(bond, rules_[bond.rule].properties, section(bond, particles));
  }
  return energy;
}

void BondSet::addTimeStepLimits(TimeStepReport& report, const std::vector<Material>& materials,
                                const std::vector<double>& minRadiusOfMaterial) const {
  for (const BondRule& rule : rules_) {
    // The lightest sphere the rule can bond: the smallest of its materials.
    double radius = 0.0;
    double mass = std::numeric_limits<double>::infinity();
    for (std::size_t m = 0; m < materials.size(); ++m) {
      const double r = minRadiusOfMaterial[m];
      if (r <= 0.0) continue;
      if (!rule.materials.empty() && std::find(rule.materials.begin(), rule.materials.end(), m) == rule.materials.end()) {
        continue;
      }
      const double sphere = sphereMass(r, materials[m].density);
      if (sphere < mass) {
        mass = sphere;
        radius = r;
      }
    }
    if (radius <= 0.0) continue;
    const ParallelBondProperties& k = rule.properties;
    const BondSection s = BondSection::of(k.radius_multiplier, radius, radius);
    const double axial = std::max(k.normal_stiffness_per_area, k.shear_stiffness_per_area) * s.area;  // [N/m]
    const double rotational = k.shear_stiffness_per_area * s.area * radius * radius +
                              std::max(k.normal_stiffness_per_area * s.inertia,
                                       k.shear_stiffness_per_area * s.polar);  // [N m/rad]
    const double inertia = 0.4 * mass * radius * radius;
    const double z = kBondCoordinationBound;
    report.addConstraint({"parallel_bonds " + rule.name + " axial",
                          fmt::format("bond stiffness max(kn, ks) A = {:.6g} N/m on the lightest bonded sphere "
                                      "({:.6g} kg, R = {:.6g} m), up to {:g} bonds a sphere: dt < 2 / omega, "
                                      "omega^2 = 2 Z k / m; softer bonds or bigger spheres relax it",
                                      axial, mass, radius, z),
                          2.0 / std::sqrt(2.0 * z * axial / mass)});
    report.addConstraint({"parallel_bonds " + rule.name + " rotational",
                          fmt::format("bond rotational stiffness ks A R^2 + max(kn I, ks J) = {:.6g} N m on the "
                                      "lightest bonded sphere (moment of inertia {:.6g} kg m^2), up to {:g} bonds a "
                                      "sphere: dt < 2 / omega, omega^2 = 2 Z k / I",
                                      rotational, inertia, z),
                          2.0 / std::sqrt(2.0 * z * rotational / inertia)});
  }
}

void BondSet::save(StateWriter& out) const {
  out.writeVector(made_);
  out.write(counts_.intact);
  out.write(counts_.broken);
  out.write(counts_.dropped);
  out.write<std::uint64_t>(bonds_.size());
  for (const ParallelBond& bond : bonds_) {
    out.write(bond.id_a);
    out.write(bond.id_b);
    out.write(bond.rule);
    out.write(static_cast<std::uint8_t>(bond.broken));
    out.write(bond.normal);
    out.write(bond.normal_force);
    out.write(bond.shear_force);
    out.write(bond.twisting_moment);
    out.write(bond.bending_moment);
  }
}

void BondSet::restore(StateReader& in, const ParticleArrays& particles) {
  std::vector<char> made = in.readVector<char>();
  if (made.size() != rules_.size()) {
    in.fail(std::to_string(made.size()) + " bond rules", "the scene declares " + std::to_string(rules_.size()));
  }
  BondCounts counts;
  counts.intact = in.read<std::uint64_t>();
  counts.broken = in.read<std::uint64_t>();
  counts.dropped = in.read<std::uint64_t>();
  const auto count = in.read<std::uint64_t>();
  in.requireAvailable(count, 2 * sizeof(std::uint64_t), "bonds");
  std::unordered_map<std::uint64_t, std::uint32_t> slotOf;
  for (std::uint32_t i = 0; i < particles.size(); ++i) slotOf.emplace(particles.id[i], i);
  const auto slot = [&](std::uint64_t id) {
    const auto it = slotOf.find(id);
    if (it == slotOf.end()) in.fail(std::to_string(id), "a bond names a particle the checkpoint does not hold");
    return it->second;
  };
  std::vector<ParallelBond> bonds(count);
  std::uint64_t intact = 0;
  for (ParallelBond& bond : bonds) {
    bond.id_a = in.read<std::uint64_t>();
    bond.id_b = in.read<std::uint64_t>();
    bond.rule = in.read<std::uint32_t>();
    if (bond.rule >= rules_.size()) in.fail(std::to_string(bond.rule), "bond rule index out of range");
    bond.broken = in.read<std::uint8_t>() != 0;
    bond.normal = in.read<Vec3>();
    bond.normal_force = in.read<double>();
    bond.shear_force = in.read<Vec3>();
    bond.twisting_moment = in.read<double>();
    bond.bending_moment = in.read<Vec3>();
    bond.slot_a = slot(bond.id_a);
    bond.slot_b = slot(bond.id_b);
    if (!bond.broken) ++intact;
  }
  in.requireEnd();
  if (intact != counts.intact) {
    in.fail(std::to_string(counts.intact), "intact bond count differs from the " + std::to_string(intact) +
                                                " intact bonds listed");
  }
  made_ = std::move(made);
  counts_ = counts;
  bonds_ = std::move(bonds);
}

}  // namespace demlink::core
