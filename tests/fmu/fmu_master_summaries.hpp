#pragma once
/// What fmu_master's summary line must contain after each scenario, on Linux (test_fmu.cpp)
/// and under wine (tests/windows): the step counts follow from plate_in_bed.cfg and
/// short_run.cfg with the master's constants.
namespace demlink::fmu {

/// The plate lowered from 0.11 m to 0.05 m at 0.25 m/s in 2 ms steps, both ends included.
inline constexpr const char* kPlateSummary = "121 steps";
/// short_run.cfg's box ends at 10 ms: steps 0..5 succeed, the next one is fmi2Discard (2)
/// with fmi2Terminated set.
inline constexpr const char* kEndSummary = "end after 6 steps, status 2, terminated 1";

}  // namespace demlink::fmu
