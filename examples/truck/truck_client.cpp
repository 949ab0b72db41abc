/// demlink-truck: the truck of the excavator-and-truck co-simulation, a system model
/// coupled through the C ABI only (demlink_c.h, generic packages as in the coupling
/// paper: dl_set_data / dl_send_package / dl_recv_package).
///
/// Why the C ABI and generic packages: this is the path a Modelica tool takes, and the
/// example is its executable check at full scale. Generic packages are needed anyway for
/// what the typed helpers do not carry: the frame motion input, expected names, the VTK
/// interval, and an STL body whose bytes are sent from the client.
///
/// The client declares the SimulationBox (it must, because it moves the simulation's frame
/// while the truck drives), the dump body (RigidBody, LAGGED: the pose sent at sample k is
/// the model's pose at sample k+1, reached by the mesh over the interval), the load sensor
/// (RegionSensor attached to the body) and, in the `source` scenario, a ParticleSource over
/// the bed. One exchange per communication interval; the suspension model (truck_model.hpp)
/// takes one RK4 step per interval with the DEM wrench of the interval that just ended.
/// Phases: loading -> settling -> holding (at rest, the static reference) -> accelerating
/// -> turning -> done (frame inertial again, Bye). With --stand-still the truck never drives
/// (for engines without a moving frame, such as the LIGGGHTS backend): holding -> done, and
/// no package ever carries a frame motion; the body still rides on its suspension and the
/// load is reported as before.
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <sys/stat.h>

#include "../cosim/site_layout.hpp"
#include "demlink/cli/command_line.hpp"
#include "demlink/demlink_c.h"
#include "dump_body_mesh.hpp"
#include "truck_model.hpp"

namespace {

namespace site = demlink::examples::site;
namespace cli = demlink::cli;
using demlink::examples::truck::DumpBodyShape;
using demlink::examples::truck::TruckInputs;
using demlink::examples::truck::TruckModel;
using demlink::examples::truck::TruckParameters;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// Component names (the excavator and the scene file use others).
constexpr const char* kFrameName = "truck_frame";
constexpr const char* kBodyName = "truck_body";
constexpr const char* kLoadName = "truck_load";
constexpr const char* kFeederName = "truck_feeder";

struct Options {
  std::string host = site::kDefaultHost;
  int port = static_cast<int>(site::kDefaultPort);
  bool source = false;  ///< scenario: false excavator, true source
  bool expected_given = false;
  std::vector<std::string> expected;  ///< the other clients' component names
  std::string output = "out/truck";
  double load_target = 1000.0;  ///< [kg] source scenario: mass the source inserts
  double source_rate = 500.0;   ///< [kg/s]
  double drive_time = 3.0;      ///< [s] accelerating half, turning half
  double drive_at = 0.0;        ///< [s] excavator scenario: start driving at this time (0: after `dumps` dumps)
  int dumps = 2;                ///< excavator scenario: drive once this many dumps have settled (demlink-excavator's default cycles)
  double acceleration = 1.5;    ///< [m/s^2]
  double yaw_rate = 0.5;        ///< [rad/s] (left turn)
  double body_mass = 2000.0;    ///< [kg]
  double steady_time = 0.4;     ///< [s] load unchanged this long = settled
  double max_time = 0.0;        ///< [s] start driving at the latest here (0: source 30 s, excavator 600 s)
  double timeout = 300.0;       ///< [s] bound of every wait for the server (the compile may generate a pit)
  double log_interval = 0.5;    ///< [s] simulated time between log lines; 0: every sample
  bool stand_still = false;     ///< never move the frame: holding -> done
  int fidelity = 0;             ///< SimulationBox.fidelity: 0 none, 1 draft, 2 engineering, 3 validation
  double modulus_scale = 0.0;   ///< SimulationBox.modulus_scale; 0: not given
  double time_step = 0.0;       ///< [s] 0: the preset's step for the site (site_layout.hpp), or kTimeStep
  std::string material = "gravel";
};

std::vector<std::string> splitNames(const std::string& list) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = list.find(',', start);
    const std::string item = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (!item.empty()) out.push_back(item);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

/// Parses the command line (demlink/cli/command_line.hpp); an exit code when the program
/// should stop now (--help, --version: 0; bad input: 2, naming the option and the value).
std::optional<int> parse(int argc, char** argv, Options& o) {
  CLI::App app("The truck of the excavator-and-truck co-simulation: a system model coupled through the C ABI.",
               "demlink-truck");
  cli::addText(app, "--host", o.host, "server address (default 127.0.0.1)")->type_name("H");
  cli::addWholeNumber(app, "--port", o.port, 1, 65535, "server port (default 47000)");
  cli::addValue(app, "--scenario", "excavator (load from demlink-excavator, default) or source (a particle source)",
                [&o](const std::string& text) {
                  if (text != "excavator" && text != "source") cli::refuse("--scenario", text, "expected excavator or source");
                  o.source = text == "source";
                })
      ->type_name("excavator|source");
  cli::addValue(app, "--expected", "the other clients' component names (default: bucket,bucket_fill)",
                [&o](const std::string& text) {
                  o.expected = splitNames(text);
                  o.expected_given = true;
                })
      ->type_name("N1,N2,...");
  cli::addText(app, "--output", o.output, "output directory (default out/truck)")->type_name("DIR");
  cli::addNumber(app, "--load-target", o.load_target, {0.0, true}, "source scenario: mass the source inserts [kg] (default 1000)")
      ->type_name("KG");
  cli::addNumber(app, "--source-rate", o.source_rate, {0.0, true}, "source scenario: insertion rate [kg/s] (default 500)")
      ->type_name("KG_PER_S");
  cli::addNumber(app, "--drive-time", o.drive_time, {0.0}, "driving time, accelerating half, turning half [s] (default 3)")
      ->type_name("S");
  cli::addNumber(app, "--drive-at", o.drive_at, {0.0},
                 "excavator scenario: start driving at this time [s] (default 0: after --dumps dumps)")
      ->type_name("S");
  cli::addWholeNumber(app, "--dumps", o.dumps, 1, 1000,
                      "excavator scenario: drive once this many dumps have settled (default 2)");
  cli::addNumber(app, "--acceleration", o.acceleration, {0.0}, "[m/s^2] (default 1.5)")->type_name("M_S2");
  cli::addNumber(app, "--yaw-rate", o.yaw_rate, {-10.0}, "[rad/s], left turn > 0 (default 0.5)")->type_name("RAD_S");
  cli::addNumber(app, "--body-mass", o.body_mass, {1.0}, "dump body mass [kg] (default 2000)")->type_name("KG");
  cli::addNumber(app, "--steady-time", o.steady_time, {0.0}, "load unchanged this long = settled [s] (default 0.4)")
      ->type_name("S");
  cli::addNumber(app, "--max-time", o.max_time, {0.0},
                 "start driving at the latest here [s] (default 0: source 30 s, excavator 600 s)")
      ->type_name("S");
  cli::addText(app, "--material", o.material, "material of the source's particles (default gravel)")->type_name("NAME");
  cli::addNumber(app, "--timeout", o.timeout, {1e-3}, "bound of every wait for the server [s] (default 300)")
      ->type_name("S");
  cli::addNumber(app, "--log-interval", o.log_interval, {0.0},
                 "simulated time between log lines [s] (default 0.5; 0: every sample)")
      ->type_name("S");
  app.add_flag("--stand-still", o.stand_still,
               "never drive: no frame motion is sent (for the LIGGGHTS backend); the body still rides on its "
               "suspension, the load is reported, and the truck says Bye after holding");
  cli::addValue(app, "--fidelity",
                 "the simulation box's fidelity preset, draft, engineering or validation: the speed/accuracy "
                 "choices it sets and the site's time step for it (default: none, a 0.2 ms step at a 10 % "
                 "restitution tolerance)",
                 [&o](const std::string& text) {
                   const std::array<const char*, 3> names{"draft", "engineering", "validation"};
                   const auto it = std::find(names.begin(), names.end(), text);
                   if (it == names.end()) cli::refuse("--fidelity", text, "expected draft, engineering or validation");
                   o.fidelity = static_cast<int>(it - names.begin()) + 1;
                 })
      ->type_name("PRESET");
  cli::addNumber(app, "--time-step", o.time_step, {0.0, true},
                 "DEM time step [s] (default: the preset's step for the site, or 2e-4); it must divide the 1 ms "
                 "communication interval")
      ->type_name("S");
  cli::addNumber(app, "--modulus-scale", o.modulus_scale, {0.0, true},
                 "softening factor of every Young's modulus for the contacts, in (0, 1] (SimulationBox.modulus_scale, "
                 "docs/accuracy.md \"Softening\"): 0.2 allows --time-step 1e-3 and halves the digging force "
                 "(default: 1, none)")
      ->type_name("S");
  if (const std::optional<int> exitCode = cli::parse(app, argc, argv)) return exitCode;
  if (!o.expected_given && !o.source) o.expected = {"bucket", "bucket_fill"};  // demlink-excavator's components
  if (o.max_time <= 0.0) o.max_time = o.source ? 30.0 : 600.0;
  return std::nullopt;
}

/// Creates DIR and its parents (like mkdir -p).
void makeDirectories(const std::string& path) {
  for (std::size_t pos = 1; pos <= path.size(); ++pos) {
    if (pos == path.size() || path[pos] == '/') {
      const std::string prefix = path.substr(0, pos);
      if (::mkdir(prefix.c_str(), 0755) != 0 && errno != EEXIST) {
        throw std::runtime_error("cannot create directory '" + prefix + "': " + std::strerror(errno));
      }
    }
  }
}

/// A C ABI client with error checks that turn a failed call into an exception naming it.
class Link {
 public:
  Link() : client_(dl_client_create()), package_(dl_package_create()) {
    if (client_ == nullptr || package_ == nullptr) throw std::runtime_error("out of memory");
  }
  ~Link() {
    dl_package_destroy(package_);
    dl_client_destroy(client_);
  }
  Link(const Link&) = delete;
  Link& operator=(const Link&) = delete;

  void check(int status, const char* what) const {
    if (status == DL_OK) return;
    if (status == DL_ERR_FINISHED) throw std::runtime_error(std::string(what) + ": " + dl_last_error(client_));
    throw std::runtime_error(std::string(what) + " failed (status " + std::to_string(status) + "): " +
                             dl_last_error(client_));
  }
  dl_client* client() { return client_; }

  /// Sends one generic package (declaration when strings are given, else inputs).
  void send(const std::vector<long long>& ints, const std::vector<double>& reals,
            const std::vector<std::string>& strings, const char* what) {
    std::vector<const char*> raw;
    for (const auto& s : strings) raw.push_back(s.c_str());
    check(dl_set_data(package_, ints.data(), static_cast<int>(ints.size()), reals.data(),
                      static_cast<int>(reals.size()), raw.data(), static_cast<int>(raw.size())),
          what);
    check(dl_send_package(client_, package_), what);
  }
  /// Receives the next answer; returns its handle and fills reals / ints.
  int receive(std::vector<double>& reals, std::vector<long long>& ints) {
    check(dl_recv_package(client_, package_), "dl_recv_package");
    return unpack(reals, ints);
  }
  /// The latest (initial) outputs of a component.
  void outputs(int handle, std::vector<double>& reals, std::vector<long long>& ints) {
    check(dl_get_outputs(client_, handle, package_), "dl_get_outputs");
    unpack(reals, ints);
  }

 private:
  int unpack(std::vector<double>& reals, std::vector<long long>& ints) {
    int n = 0;
    check(dl_get_reals(package_, nullptr, 0, &n), "dl_get_reals");
    reals.assign(static_cast<std::size_t>(n), 0.0);
    if (n > 0) check(dl_get_reals(package_, reals.data(), n, &n), "dl_get_reals");
    check(dl_get_ints(package_, nullptr, 0, &n), "dl_get_ints");
    ints.assign(static_cast<std::size_t>(n), 0);
    if (n > 0) check(dl_get_ints(package_, ints.data(), n, &n), "dl_get_ints");
    return ints.empty() ? -1 : static_cast<int>(ints[0]);
  }

  dl_client* client_;
  dl_package* package_;
};

enum class Phase { Loading, Settling, Holding, Accelerating, Turning, Done };

const char* phaseName(Phase p) {
  switch (p) {
    case Phase::Loading: return "loading";
    case Phase::Settling: return "settling";
    case Phase::Holding: return "holding";
    case Phase::Accelerating: return "accelerating";
    case Phase::Turning: return "turning";
    case Phase::Done: return "done";
  }
  return "?";
}

/// Quaternion (w, x, y, z) of pitch theta about y, then roll phi about x (body axes).
std::array<double, 4> attitude(double theta, double phi) {
  const double cy = std::cos(0.5 * theta), sy = std::sin(0.5 * theta);
  const double cx = std::cos(0.5 * phi), sx = std::sin(0.5 * phi);
  // q_y * q_x
  return {cy * cx, cy * sx, sy * cx, -sy * sx};
}

/// Rotates v by the quaternion q (w, x, y, z).
std::array<double, 3> rotate(const std::array<double, 4>& q, const std::array<double, 3>& v) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  // t = 2 q_vec x v; v' = v + w t + q_vec x t
  const double tx = 2.0 * (y * v[2] - z * v[1]);
  const double ty = 2.0 * (z * v[0] - x * v[2]);
  const double tz = 2.0 * (x * v[1] - y * v[0]);
  return {v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)};
}

int run(const Options& o) {
  makeDirectories(o.output);
  const double tc = site::kCommunicationInterval;
  const DumpBodyShape shape{site::kTruckBedLength, site::kTruckBedWidth, site::kTruckBedWallHeight, 0.08, 0.1};
  const std::string stlPath = o.output + "/truck_body.stl";
  demlink::examples::truck::writeBinaryStl(stlPath, demlink::examples::truck::dumpBodyTriangles(shape));

  TruckParameters params;
  params.body_mass = o.body_mass;
  // Inertia of a solid block 3.4 x 2.4 x 1.0 m of the body's mass (a simple estimate).
  params.pitch_inertia = o.body_mass * (3.4 * 3.4 + 1.0) / 12.0;
  params.roll_inertia = o.body_mass * (2.4 * 2.4 + 1.0) / 12.0;
  // Spring rate for a heave frequency of about 1.5 Hz under the empty body, damping ratio 0.35.
  const double omega = 2.0 * M_PI * 1.5;
  params.spring_stiffness = 0.25 * o.body_mass * omega * omega;
  params.spring_damping = 0.25 * 2.0 * 0.35 * o.body_mass * omega;
  TruckModel model(params);
  // Centre of gravity in the body frame (origin: centre of the floor's top surface).
  const std::array<double, 3> cgLocal{0.0, 0.0, -0.35};
  const std::array<double, 3> bodyOrigin{site::kTruckBedX, site::kTruckBedY, site::kTruckBedFloorZ};
  const std::array<double, 3> cgRest{bodyOrigin[0] + cgLocal[0], bodyOrigin[1] + cgLocal[1], bodyOrigin[2] + cgLocal[2]};

  Link link;
  link.check(dl_set_timeout(link.client(), o.timeout), "dl_set_timeout");
  // The server's access token, as demlink-server reads it (docker/compose.yaml sets it).
  const char* token = std::getenv("DEMLINK_TOKEN");
  link.check(dl_connect_to_host(link.client(), o.host.c_str(), o.port, "truck", token != nullptr ? token : ""),
             "dl_connect_to_host");

  // SimulationBox: the whole site, run until Bye, VTK every 0.25 s, 2 threads, and a
  // restitution tolerance of 10 % instead of the default 1 %: it trades accuracy for speed
  // (the site's step, chosen for a real-time pace, is not held to the 1 % limit). The
  // watchdog stops at overlaps of 0.7 of the smaller radius instead of 0.5: the site's
  // gravel is softened to E = 5e7 Pa for that step, and a grain jammed between the bucket
  // and the pit carries tens of kN (0.5 of a 60 mm radius is ~35 kN); whether one jams
  // that hard depends on round-off (one summation order of the pair forces reached 0.534,
  // the run then went on normally). The energy check still stops a blow-up.
  // With a fidelity preset the preset sets the tolerance (NaN: not given) and the site's
  // step for it is used (site_layout.hpp).
  std::vector<std::string> boxStrings{"simulation_box", kFrameName, kFrameName, kBodyName, kLoadName};
  if (o.source) boxStrings.emplace_back(kFeederName);
  for (const auto& n : o.expected) boxStrings.push_back(n);
  const std::array<double, 4> presetStep{site::kTimeStep, site::kDraftTimeStep, site::kEngineeringTimeStep,
                                         site::kValidationTimeStep};
  const double timeStep = o.time_step > 0.0 ? o.time_step : presetStep[static_cast<std::size_t>(o.fidelity)];
  const double tolerance = o.fidelity == 0 ? 0.1 : kNan;
  link.send({0, 2, 0, 0, o.fidelity},
            {tc, timeStep, 0.0, 0.0, 0.0, -9.81, -5.0, -6.5, -2.0, 9.5, 3.0, 5.0, 0.25, tolerance, kNan, kNan, 0.7,
             o.modulus_scale > 0.0 ? o.modulus_scale : kNan},
            boxStrings,
            "declare simulation_box");
  // The dump body: STL bytes sent from here, reference point = the body frame's origin.
  link.send({2, 2},
            {tc, 0.0, 0.0, 0.0, bodyOrigin[0], bodyOrigin[1], bodyOrigin[2], 1.0, 0.0, 0.0, 0.0},
            {"rigid_body", kBodyName, o.material, stlPath}, "declare rigid_body");
  // Load sensor: the cavity and up to 0.15 m of heap above the walls, riding with the body.
  // Why so little heap: a loaded bucket swinging in passes a metre above the rim, and a
  // taller box counted its contents for a moment before the dump (a few bucket loads
  // heap far less than the 0.6 m walls).
  const double sensorHeight = site::kTruckBedWallHeight + 0.15;
  link.send({0}, {tc, 0.0, 0.0, 0.5 * sensorHeight, site::kTruckBedLength, site::kTruckBedWidth, sensorHeight},
            {"region_sensor", kLoadName, kBodyName}, "declare region_sensor");
  const double sourceStop = o.load_target / o.source_rate;
  if (o.source) {
    const double z = site::kTruckBedFloorZ + site::kTruckBedWallHeight + 0.15;
    link.send({7},
              {tc, site::kTruckBedX, site::kTruckBedY, z, 0.5 * site::kTruckBedLength - 0.3,
               0.5 * site::kTruckBedWidth - 0.3, 0.12, site::kGravelRadiusMin, site::kGravelRadiusMax, kNan,
               o.source_rate, 0.0, 0.0, -0.5, 0.0, sourceStop},
              {"particle_source", kFeederName, o.material, ""}, "declare particle_source");
  }
  const int kFrame = 0, kBody = 1, kLoad = 2, kFeeder = 3;
  const int components = o.source ? 4 : 3;
  std::printf("demlink-truck: declared %s, %s, %s%s%s; waiting for compile (expected:", kFrameName, kBodyName, kLoadName,
              o.source ? ", " : "", o.source ? kFeederName : "");
  for (std::size_t i = 2; i < boxStrings.size(); ++i) std::printf(" %s", boxStrings[i].c_str());
  std::printf(")\n");
  std::fflush(stdout);
  link.check(dl_wait_compiled(link.client()), "dl_wait_compiled");

  const std::string csvPath = o.output + "/truck.csv";
  std::FILE* csv = std::fopen(csvPath.c_str(), "w");
  if (csv == nullptr) throw std::runtime_error("cannot write '" + csvPath + "'");
  std::fprintf(csv,
               "# body_mass_kg=%g cg_above_seats_m=%g front_axle_x_m=%g rear_axle_x_m=%g half_track_m=%g "
               "cg_z_m=%g acceleration_m_s2=%g yaw_rate_rad_s=%g\n",
               params.body_mass, -params.seat_height, params.front_axle_x, params.rear_axle_x, params.half_track,
               cgRest[2], o.acceleration, o.yaw_rate);
  std::fprintf(csv,
               "time_s,phase,load_mass_kg,load_count,load_com_x_m,load_com_y_m,load_com_z_m,inserted_mass_kg,"
               "spring_fl_N,spring_fr_N,spring_rl_N,spring_rr_N,axle_front_N,axle_rear_N,side_left_N,side_right_N,"
               "heave_m,pitch_rad,roll_rad,dem_fx_N,dem_fy_N,dem_fz_N,dem_mx_Nm,dem_my_Nm,dem_mz_Nm,"
               "frame_ax_m_s2,frame_ay_m_s2,frame_az_m_s2,yaw_rate_rad_s,speed_m_s\n");

  // Latest outputs per component.
  std::vector<double> reals;
  std::vector<long long> ints;
  std::array<double, 12> wrench{};
  double loadMass = 0.0;
  long long loadCount = 0;
  std::array<double, 3> loadCom{kNan, kNan, kNan};
  double inserted = 0.0;
  const auto take = [&](int handle) {
    if (handle == kBody) {
      for (std::size_t i = 0; i < 12 && i < reals.size(); ++i) wrench[i] = reals[i];
    } else if (handle == kLoad && reals.size() >= 4) {
      loadMass = reals[0];
      loadCount = ints.size() > 2 ? ints[2] : 0;
      loadCom = {reals[1], reals[2], reals[3]};
    } else if (handle == kFeeder && reals.size() >= 2) {
      inserted = reals[1];
    }
  };
  for (int h = 0; h < components; ++h) {
    link.outputs(h, reals, ints);
    take(h);
  }

  Phase phase = Phase::Loading;
  double phaseStart = 0.0;
  double massRef = 0.0, massChangedAt = 0.0, stillSince = 0.0;
  // Dumps so far: a settled rise of the load by more than kDumpMinimum over the last settled load.
  constexpr double kDumpMinimum = 20.0;  // [kg]
  double settledLoad = 0.0;
  int dumps = 0;
  double speed = 0.0, yawRate = 0.0;
  const double accelerateTime = 0.5 * o.drive_time, turnTime = 0.5 * o.drive_time;
  const double yawRamp = std::min(0.25, 0.5 * turnTime);
  double nextLog = 0.0;
  int doneSamples = 0;

  for (long long k = 0;; ++k) {
    if (k > 0) {
      for (int n = 0; n < components; ++n) take(link.receive(reals, ints));
    }
    const double t = static_cast<double>(k) * tc;

    // Phase logic (at sample k, for the interval [t, t + tc]).
    if (std::fabs(loadMass - massRef) > std::max(1.0, 0.005 * massRef)) {
      massRef = loadMass;
      massChangedAt = t;
    }
    // Settled: the sensed mass unchanged for steady_time, the body nearly still, and the
    // body carrying the sensed load's weight (the particles no longer bounce).
    const double weightError = std::fabs(wrench[2] + loadMass * params.gravity);
    if (std::fabs(model.state().z_rate) > 2e-3 || std::fabs(model.state().theta_rate) > 2e-3 ||
        std::fabs(model.state().phi_rate) > 2e-3 || weightError > 0.01 * (params.body_mass + loadMass) * params.gravity) {
      stillSince = t;
    }
    const bool steady = t - massChangedAt >= o.steady_time && t - stillSince >= 0.1;
    if (steady && loadMass > settledLoad + kDumpMinimum) {
      ++dumps;
      std::printf("demlink-truck: t = %.3f s: dump %d settled: load %.1f kg (+%.1f kg)\n", t, dumps, loadMass,
                  loadMass - settledLoad);
      std::fflush(stdout);
    }
    if (steady) settledLoad = loadMass;
    const auto enter = [&](Phase p) {
      phase = p;
      phaseStart = t;
      std::printf("demlink-truck: t = %.3f s: %s (load %.1f kg)\n", t, phaseName(p), loadMass);
      std::fflush(stdout);
    };
    switch (phase) {
      case Phase::Loading: {
        const bool over = o.source ? t >= sourceStop
                                   : ((o.drive_at > 0.0 && t >= o.drive_at) || (o.drive_at <= 0.0 && dumps >= o.dumps && steady));
        if (over || t >= o.max_time) enter(o.source ? Phase::Settling : Phase::Holding);
        break;
      }
      case Phase::Settling:
        if ((steady && t - phaseStart >= o.steady_time) || t >= o.max_time) enter(Phase::Holding);
        break;
      case Phase::Holding:
        if (t - phaseStart >= 0.2) enter(o.stand_still ? Phase::Done : Phase::Accelerating);
        break;
      case Phase::Accelerating:
        if (t - phaseStart >= accelerateTime - 0.5 * tc) enter(Phase::Turning);
        break;
      case Phase::Turning:
        if (t - phaseStart >= turnTime - 0.5 * tc) enter(Phase::Done);
        break;
      case Phase::Done:
        break;
    }

    // Frame motion for this interval (truck frame, origin at the body's centre of gravity).
    std::array<double, 3> frameAcc{0.0, 0.0, 0.0};
    double yawAcc = 0.0;
    if (phase == Phase::Accelerating) {
      frameAcc[0] = o.acceleration;
    } else if (phase == Phase::Turning) {
      yawAcc = t - phaseStart < yawRamp ? o.yaw_rate / yawRamp : 0.0;
      frameAcc[1] = speed * (yawRate + 0.5 * yawAcc * tc);
    }

    // DEM wrench on the body, torque moved from the reference point to the CG.
    const auto q = attitude(model.state().theta, model.state().phi);
    const auto arm = rotate(q, {-cgLocal[0], -cgLocal[1], -cgLocal[2]});  // CG -> reference point
    TruckInputs in;
    for (std::size_t i = 0; i < 3; ++i) in.dem_force[i] = wrench[i];
    in.dem_torque = {wrench[3] + arm[1] * wrench[2] - arm[2] * wrench[1],
                     wrench[4] + arm[2] * wrench[0] - arm[0] * wrench[2],
                     wrench[5] + arm[0] * wrench[1] - arm[1] * wrench[0]};
    in.frame_acceleration = frameAcc;

    // Log the state at t with the wrench of the interval that ended at t.
    const auto f = model.springForces();
    const auto& s = model.state();
    // An empty load has no centre of mass (NaN from the C ABI): empty cells, DEMLink's
    // missing value in every CSV, never the text "nan".
    char com[96] = ",,";
    if (!std::isnan(loadCom[0])) std::snprintf(com, sizeof com, "%.5f,%.5f,%.5f", loadCom[0], loadCom[1], loadCom[2]);
    std::fprintf(csv,
                 "%.4f,%s,%.4f,%lld,%s,%.4f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.7f,%.7f,%.7f,"
                 "%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.4f,%.4f,%.4f,%.5f,%.5f\n",
                 t, phaseName(phase), loadMass, loadCount, com, inserted, f[0], f[1],
                 f[2], f[3], f[0] + f[1], f[2] + f[3], f[0] + f[2], f[1] + f[3], s.z, s.theta, s.phi, in.dem_force[0],
                 in.dem_force[1], in.dem_force[2], in.dem_torque[0], in.dem_torque[1], in.dem_torque[2], frameAcc[0],
                 frameAcc[1], frameAcc[2], yawRate, speed);
    if (t >= nextLog - 1e-9) {
      std::printf("t %7.3f s  %-12s load %8.1f kg (%4lld)  axles F %8.0f N  R %8.0f N  heave %+7.4f m  pitch %+7.4f rad"
                  "  roll %+7.4f rad\n",
                  t, phaseName(phase), loadMass, loadCount, f[0] + f[1], f[2] + f[3], s.z, s.theta, s.phi);
      std::fflush(stdout);
      nextLog += o.log_interval;
    }

    if (phase == Phase::Done && ++doneSamples > 1) break;

    // Advance the model to t + tc and send the pose it reaches (LAGGED: the mesh gets there
    // over the interval), the frame motion and the other components' empty packages.
    model.step(in, tc);
    const auto& n = model.state();
    const auto qn = attitude(n.theta, n.phi);
    const auto armN = rotate(qn, {-cgLocal[0], -cgLocal[1], -cgLocal[2]});
    const std::array<double, 3> omegaBody{n.phi_rate, n.theta_rate, 0.0};
    const std::array<double, 3> position{cgRest[0] + armN[0], cgRest[1] + armN[1], cgRest[2] + n.z + armN[2]};
    const std::array<double, 3> velocity{omegaBody[1] * armN[2] - omegaBody[2] * armN[1],
                                         omegaBody[2] * armN[0] - omegaBody[0] * armN[2],
                                         n.z_rate + omegaBody[0] * armN[1] - omegaBody[1] * armN[0]};
    const double yawNext = yawRate + yawAcc * tc;
    if (!o.stand_still && (phase == Phase::Accelerating || phase == Phase::Turning || phase == Phase::Done)) {
      link.send({kFrame},
                {kNan, kNan, kNan, frameAcc[0], frameAcc[1], frameAcc[2], 0.0, 0.0, phase == Phase::Done ? 0.0 : yawRate,
                 0.0, 0.0, phase == Phase::Done ? 0.0 : yawAcc, cgRest[0], cgRest[1], 0.0},
                {}, "send simulation_box");
    } else {
      link.send({kFrame}, {}, {}, "send simulation_box");
    }
    link.send({kBody},
              {position[0], position[1], position[2], qn[0], qn[1], qn[2], qn[3], velocity[0], velocity[1], velocity[2],
               omegaBody[0], omegaBody[1], omegaBody[2]},
              {}, "send rigid_body");
    link.send({kLoad}, {}, {}, "send region_sensor");
    if (o.source) link.send({kFeeder}, {}, {}, "send particle_source");
    speed += frameAcc[0] * tc;
    yawRate = phase == Phase::Turning ? yawNext : 0.0;
  }
  std::fclose(csv);
  link.check(dl_finish(link.client(), "truck finished driving"), "dl_finish");
  link.check(dl_wait_finished(link.client()), "dl_wait_finished");
  std::printf("demlink-truck: finished (%s); load %.1f kg (%lld particles)%s; wrote %s\n",
              dl_finished_reason(link.client()), loadMass, loadCount,
              o.source ? (", inserted " + std::to_string(inserted) + " kg").c_str() : "", csvPath.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (const std::optional<int> exitCode = parse(argc, argv, options)) return *exitCode;
  try {
    return run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "demlink-truck: %s\n", e.what());
    return 1;
  }
}
