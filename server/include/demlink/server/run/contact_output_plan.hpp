#pragma once
/// What a run asks of the world's contact output, for the runners to set before
/// world.initialize(): the initialising force evaluation is then recorded, so the contact
/// series (contacts.pvd) and the mesh loads get a frame at step 0 like the particles.
/// RunDriver asks for the same settings again, which keeps those records
/// (World::setContactOutput).
#include "demlink/core/contact/contact_record.hpp"
#include "demlink/server/run/run_driver.hpp"
#include "demlink/server/scene/run_options.hpp"

namespace demlink::server {

/// The contact output `run` asks for under `plan` (inactive when it asks for none).
[[nodiscard]] inline core::ContactOutputSettings contactOutputOf(const RunOptions& run, const RunPlan& plan) {
  return {plan.contact_every, run.mesh_loads};
}

}  // namespace demlink::server
