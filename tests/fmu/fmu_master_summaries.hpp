#pragma once
/// What fmu_master's summary line must contain after each scenario, on Linux (test_fmu.cpp)
/// and under wine (tests/windows): the step counts follow from plate_in_bed.cfg,
/// short_run.cfg and short_run_receive_first.cfg with the master's constants.
namespace demlink::fmu {

/// The plate lowered from 0.11 m to 0.05 m at 0.25 m/s in 2 ms steps, both ends included.
inline constexpr const char* kPlateSummary = "121 steps";
/// short_run.cfg's box ends at 10 ms: send first, the fifth step's outputs end there, the
/// sixth step is fmi2Discard (2) with fmi2Terminated set.
inline constexpr const char* kEndSummary = "end after 5 steps, status 2, terminated 1, send_first";
/// The same receive first: each step's outputs end at its start, so one more step succeeds.
inline constexpr const char* kReceiveFirstEndSummary = "end after 6 steps, status 2, terminated 1, receive_first";

}  // namespace demlink::fmu
