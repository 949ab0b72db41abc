#pragma once
/// The excavator-and-truck site, shared by the system models, the server's scene
/// file (examples/cosim/site_scene.json must agree) and the tests. World frame: z up,
/// ground level z = 0, SI units. Header-only constants, no dependencies, so both the C++
/// client (excavator) and the C ABI client (truck) can include it.
///
///   y
///   ^            +----------- pit 6 x 2 x 1 m, centre (0, 0), floor z = -1 ----------+
///   |            |                                                                   |
///   |            +-------------------------------------------------------------------+
///   |                        X excavator swing axis (0, -3.5)     [truck bed] centre (5.5, -3.5)
///   +------------------------------------------------------------------------------------> x
///
/// The excavator faces +y to dig (bucket 2.5 .. 4.5 m from its axis), swings 90 deg about z
/// (clockwise seen from above, heading 90 -> 0 deg) to face +x and dumps over the truck bed
/// (5.5 m from its axis).
namespace demlink::examples::site {

// Pit dug into the ground: x in [-3, 3], y in [-1, 1], z in [-1, 0].
inline constexpr double kPitHalfX = 3.0;  ///< [m]
inline constexpr double kPitHalfY = 1.0;  ///< [m]
inline constexpr double kPitDepth = 1.0;  ///< [m]

// Gravel (materials database "gravel"), coarse spheres so the demo runs in minutes.
inline constexpr double kGravelRadiusMin = 0.06;   ///< [m]
inline constexpr double kGravelRadiusMax = 0.075;  ///< [m]

// Excavator: vertical swing axis through (x, y) at ground level.
inline constexpr double kExcavatorX = 0.0;   ///< [m]
inline constexpr double kExcavatorY = -3.5;  ///< [m]

// Truck dump body (open box): centre of its floor's top surface at rest, inner size.
inline constexpr double kTruckBedX = 5.5;       ///< [m]
inline constexpr double kTruckBedY = -3.5;      ///< [m]
inline constexpr double kTruckBedFloorZ = 1.2;  ///< [m] top of the floor, suspension at rest under the empty body
inline constexpr double kTruckBedLength = 3.0;  ///< inner, along x [m]
inline constexpr double kTruckBedWidth = 2.0;   ///< inner, along y [m]
inline constexpr double kTruckBedWallHeight = 0.6;  ///< [m]

// Engine and exchange. The site's critical time step is 4.73e-4 s (0.2 of the Rayleigh
// time of the smallest gravel sphere; the compile report prints it); the restitution
// limit at 2 m/s is 5.8e-4 s at a 10 % tolerance and 1.06e-4 s at 1 % (gravel on steel).
// Every step divides the communication interval.
inline constexpr double kTimeStep = 2.0e-4;              ///< [s] the demo's default, 42 % of the limit
inline constexpr double kCommunicationInterval = 1.0e-3;  ///< [s] (5 steps)
// The step each fidelity preset (SimulationBox.fidelity) runs the site at: the largest
// divisor of the interval within the preset's share of the limit (docs/accuracy.md).
inline constexpr double kDraftTimeStep = 3.3333333333333335e-4;  ///< [s] 1/3 of the interval, 70 % of the limit
inline constexpr double kEngineeringTimeStep = 2.0e-4;           ///< [s] 42 %, within the preset's 50 %
inline constexpr double kValidationTimeStep = 1.0e-4;            ///< [s] 94 % of the 1 % restitution limit

// Default server address of the demo.
inline constexpr const char* kDefaultHost = "127.0.0.1";
inline constexpr unsigned kDefaultPort = 47000;

}  // namespace demlink::examples::site
