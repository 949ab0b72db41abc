#pragma once
/// The coupled-body part of the atlas: a plate whose vertical dynamics a client integrates,
/// dropped onto a settled bed, exchanged with the engine every `interval_steps` steps.
///
/// The engine side is core::CoupledMotion with PREDICTED targets, the object the
/// co-simulation host drives for a RigidBody (docs/cosim.md "Motion coupling"); the host
/// adds no physics to it, only transport. The client integrates m dv/dt = F + m g exactly
/// for a force held constant over each interval, with one of two orders:
///   SendFirst    every client's default (the C++ client's exchange(), the C ABI's
///                DL_ORDER_SEND_FIRST and _SPLIT, the Modelica package, the FMU): send the
///                state at t_k, receive the mean force over [t_k, t_k+1], integrate the
///                interval with it;
///   ReceiveFirst the C ABI's DL_ORDER_RECEIVE_FIRST and the FMU's receive_first option: at
///                t_k receive the force of the interval that ended, integrate [t_k, t_k+1]
///                with it, send: the force the body feels lags the motion by one interval.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "study_scenes.hpp"

namespace demlink::study {

enum class ClientOrder { SendFirst, ReceiveFirst };

[[nodiscard]] const char* toString(ClientOrder order);

struct CouplingCase {
  std::uint64_t interval_steps = 1;
  double mass = 0.2;  ///< plate mass [kg]
  ClientOrder order = ClientOrder::SendFirst;
};

struct CouplingResult {
  explicit CouplingResult(const CouplingCase& sweptCase) : c(sweptCase) {}
  CouplingCase c;
  double interval = 0.0;  ///< [s]
  std::string status = "ok";
  double depth = 0.0;        ///< plate bottom below the bed's surface, mean over the last quarter [m]
  double oscillation = 0.0;  ///< standard deviation of the plate height over the last quarter [m]
  double wall = 0.0;         ///< [s]
  double simulated = 0.0;    ///< [s]
  double particle_steps = 0.0;
};

/// Settles one bed (`grains` grains, `knobs`), then runs every case from that state for
/// `duration` seconds, handing each result to `done` as it finishes.
[[nodiscard]] std::vector<CouplingResult> runCoupling(const Knobs& knobs, std::size_t grains, double settle,
                                                      double duration, const std::vector<CouplingCase>& cases,
                                                      double cpuLimit,
                                                      const std::function<void(const CouplingResult&)>& done = {});

}  // namespace demlink::study
