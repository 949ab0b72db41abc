#pragma once
/// Time integration of sphere translation and rotation.
///   Velocity Verlet (default): v += a dt/2; x += v dt; forces(x, v); v += a dt/2.
///   Explicit Euler (solver paper eqs. 14-17): x += v_old dt; v += a_old dt.
/// Gravity enters as an acceleration here, not as a stored force, so
/// ParticleArrays::force holds contact forces only.
#include "demlink/core/base/math_types.hpp"
#include "demlink/core/particles/particle_arrays.hpp"
#include "demlink/core/parallel/thread_pool.hpp"

namespace demlink::core {

/// v += (F/m + g) h;  omega += (T/I) h.
void kick(ParticleArrays& p, const Vec3& gravity, double h, ThreadPool* pool = nullptr);
/// x += v dt.
void drift(ParticleArrays& p, double dt, ThreadPool* pool = nullptr);
/// What a step's first kick leaves in force and torque. kCleared: zeros, written right
/// after their last read of the step, while the lines are in cache; the force stage that
/// follows then adds into them without a clearing pass of its own over 48 bytes per
/// particle (World::firstKickAndDrift says when).
enum class ForcesAfterKick { kKept, kCleared };
/// kick(h) then drift(dt) in one pass over the particles.
void kickAndDrift(ParticleArrays& p, const Vec3& gravity, double h, double dt, ThreadPool* pool = nullptr,
                  ForcesAfterKick after = ForcesAfterKick::kKept);
/// kick(h) twice, then drift(dt), in one pass: the last step's second half kick, owed
/// (World::advance), and this step's first. The same two additions as two passes, so
/// the same bits, with one stream over the particles instead of two.
void kickTwiceAndDrift(ParticleArrays& p, const Vec3& gravity, double h, double dt, ThreadPool* pool = nullptr,
                       ForcesAfterKick after = ForcesAfterKick::kKept);
/// kickTwiceAndDrift(..., ForcesAfterKick::kCleared) on rows [begin, end) only, on the
/// calling thread (the pair loop runs it on the rows its chunks have finished:
/// World::computeForces).
void kickTwiceAndDriftRows(ParticleArrays& p, const Vec3& gravity, double h, double dt, std::size_t begin,
                           std::size_t end);
/// Paper eqs. 14-17: positions advance with the OLD velocities, then velocities
/// with the old accelerations.
void explicitEulerStep(ParticleArrays& p, const Vec3& gravity, double dt, ThreadPool* pool = nullptr);

}  // namespace demlink::core
