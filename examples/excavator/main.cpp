/// demlink-excavator: the excavator of the excavator-and-truck site as a co-simulation
/// client on the C++ client library.
///
/// It declares the bucket (a RigidBody whose mesh it generates, PREDICTED motion) and a
/// RegionSensor riding in the bucket, then runs the system model one communication
/// interval per exchange: read the DEM wrench and the fill mass of the interval that just
/// ended, let the operator move the levers, integrate the machine over the interval, send
/// the bucket's new pose and twist. Why one model step per exchange: the wrench is the
/// interval's mean, so a finer model step would only re-use the same force; the 1 ms
/// interval is already far below the hydraulics' time constants.
///
/// Outputs in --output DIR: bucket.stl, excavator.csv (one row per sample) and
/// excavator_summary.txt (key = value lines: carried mass per cycle, peak forces).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "bucket_mesh.hpp"
#include "demlink/cli/command_line.hpp"
#include "demlink/client/connection.hpp"
#include "demlink/client/rigid_body.hpp"
#include "demlink/client/sensor_components.hpp"
#include "demlink/client/session.hpp"
#include "demlink/v1/protocol.pb.h"
#include "excavator_model.hpp"
#include "excavator_operator.hpp"
#include "site_layout.hpp"

namespace ex = demlink::examples::excavator;
namespace site = demlink::examples::site;
namespace dc = demlink::client;
namespace cli = demlink::cli;

namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

struct Options {
  std::string host = site::kDefaultHost;
  unsigned port = site::kDefaultPort;
  int cycles = 2;
  std::string output = "out/excavator";
  double timeout_s = 300.0;  // the compile includes the pit generation
  double log_interval_s = 0.5;  // simulated time between log lines; 0: every sample
  double stop_at_s = 0.0;       // say Bye at this simulated time; 0: after the cycles
};

/// Parses the command line (demlink/cli/command_line.hpp); an exit code when the program
/// should stop now (--help, --version: 0; bad input: 2, naming the option and the value).
std::optional<int> parse(int argc, char** argv, Options& o) {
  CLI::App app("The excavator of the excavator-and-truck site: a co-simulation client on the C++ client library.",
               "demlink-excavator");
  cli::addText(app, "--host", o.host, "server address (default " + std::string(site::kDefaultHost) + ")")
      ->type_name("H");
  cli::addWholeNumber(app, "--port", o.port, 1u, 65535u,
                      "server port (default " + std::to_string(site::kDefaultPort) + ")");
  cli::addWholeNumber(app, "--cycles", o.cycles, 1, 100, "dig-dump cycles (default 2)");
  cli::addText(app, "--output", o.output,
               "where bucket.stl, excavator.csv and excavator_summary.txt go (default out/excavator)")
      ->type_name("DIR");
  cli::addNumber(app, "--timeout", o.timeout_s, {0.0, true, 1e6},
                 "bound of every wait for the server (default 300 s; the compile generates the pit)")
      ->type_name("S");
  cli::addNumber(app, "--log-interval", o.log_interval_s, {0.0, false, 1e6},
                 "simulated time between log lines (default 0.5 s; 0: every sample)")
      ->type_name("S");
  cli::addNumber(app, "--stop-at", o.stop_at_s, {0.0, false, 1e6},
                 "say Bye at this simulated time even if the cycles are not done [s] (default 0: after the cycles; "
                 "short test runs)")
      ->type_name("S");
  return cli::parse(app, argc, argv);
}

dc::Vec3 toClient(const ex::Vec3& v) { return {v.x(), v.y(), v.z()}; }
ex::Vec3 fromClient(const dc::Vec3& v) { return {v.x, v.y, v.z}; }

void sendPose(dc::RigidBody& bucket, const ex::ExcavatorModel& model) {
  const Eigen::Quaterniond q = model.bucketOrientation().normalized();
  bucket.setPose(toClient(model.bucketPivot()), dc::Quat{q.w(), q.x(), q.y(), q.z()});
  bucket.setVelocity(toClient(model.bucketVelocity()), toClient(model.bucketAngularVelocity()));
}

/// Per cycle: the mass carried to the truck (fill when the dump starts) and what stayed in
/// the bucket after it (fill when the swing back starts).
struct CycleRecord {
  double carried = 0.0;     ///< [kg]
  double after_dump = 0.0;  ///< [kg]
  double peak_fill = 0.0;   ///< [kg]
  double duration = 0.0;    ///< [s]
  double dig_force_peak = 0.0;  ///< [N] largest |DEM force| on the bucket while digging
  double dig_force_sum = 0.0;   ///< [N] sum of |DEM force| over the digging samples
  int dig_samples = 0;          ///< samples in penetration, drag and curl
};

/// Digging: the phases in which the bucket cuts the bed.
bool digging(ex::Phase phase) {
  return phase == ex::Phase::kPenetrate || phase == ex::Phase::kDrag || phase == ex::Phase::kCurl;
}

int run(const Options& opt) {
  std::filesystem::create_directories(opt.output);
  const ex::BucketMesh mesh = ex::makeBucketMesh();
  const std::string stl = ex::writeBucketStl(mesh, (std::filesystem::path(opt.output) / "bucket.stl").string());

  ex::OperatorOptions operatorOptions;
  operatorOptions.cycles = opt.cycles;
  ex::ExcavatorOperator op(operatorOptions);
  ex::ExcavatorModel model(ex::defaultMachine(), ex::Vec3{site::kExcavatorX, site::kExcavatorY, 0.0});
  model.setPose(op.start());

  dc::Connection connection;
  dc::ConnectOptions connectOptions;
  connectOptions.client_name = "excavator";
  // The server's access token, as demlink-server reads it (docker/compose.yaml sets it).
  if (const char* token = std::getenv("DEMLINK_TOKEN")) connectOptions.access_token = token;
  connectOptions.timeout = std::chrono::milliseconds(static_cast<long long>(opt.timeout_s * 1000.0));
  connection.connect(opt.host, static_cast<std::uint16_t>(opt.port), connectOptions);
  dc::Session session(connection);

  auto& bucket = session.add<dc::RigidBody>("bucket");
  const Eigen::Quaterniond q0 = model.bucketOrientation().normalized();
  bucket.setStlData(stl)
      .setMaterial("steel")
      .setReferencePoint({})
      .setInitialPose(toClient(model.bucketPivot()), dc::Quat{q0.w(), q0.x(), q0.y(), q0.z()})
      .setMotion(demlink::v1::RigidBody::PREDICTED);
  bucket.setCommunicationInterval(site::kCommunicationInterval);
  auto& fill = session.add<dc::RegionSensor>("bucket_fill");
  fill.setBox(toClient(ex::kFillBoxCentre), toClient(ex::kFillBoxSize)).attachTo("bucket");
  fill.setCommunicationInterval(site::kCommunicationInterval);

  std::cout << "excavator: connected to " << opt.host << ":" << opt.port << ", declaring bucket ("
            << mesh.triangles.size() << " triangles, capacity " << ex::bucketCapacity() << " m^3) and bucket_fill\n"
            << std::flush;
  session.declare();
  session.waitCompiled();
  const double interval = static_cast<double>(bucket.intervalSteps()) * session.timeStep();  // [s]
  std::cout << "excavator: compiled, time step " << session.timeStep() << " s, exchange every " << interval
            << " s, " << session.report().particle_count() << " particles\n" << std::flush;

  std::ofstream csv(std::filesystem::path(opt.output) / "excavator.csv");
  csv << "time,cycle,phase,swing_deg,boom_deg,stick_deg,bucket_deg";
  for (const auto& a : model.spec().actuators) {
    for (const char* f : {"valve", "length", "speed", "free_speed", "force", "dem_force", "load_ratio"}) {
      csv << "," << a.name << "_" << f;
    }
  }
  csv << ",bucket_x,bucket_y,bucket_z,fill_mass,fill_count,dem_fx,dem_fy,dem_fz,dem_mx,dem_my,dem_mz\n";
  csv.precision(7);

  sendPose(bucket, model);
  std::vector<CycleRecord> cycles(static_cast<std::size_t>(opt.cycles));
  std::array<double, 4> peakForce{};
  double cycleStart = 0.0;
  double nextLog = 0.0;
  ex::Phase lastPhase = op.phase();
  const auto wallStart = std::chrono::steady_clock::now();
  bool finishedEarly = false;
  while (!op.done()) {
    if (!session.exchange()) {
      finishedEarly = true;
      break;
    }
    const double t = session.time();
    if (opt.stop_at_s > 0.0 && t >= opt.stop_at_s) break;
    const ex::Vec3 force = fromClient(bucket.meanForce());
    const ex::Vec3 torque = fromClient(bucket.meanTorque());
    const double fillMass = fill.mass();
    const int cycle = op.cycle();
    const std::array<double, 4> commands = op.update(interval, model);
    model.step(interval, commands, force, torque);
    sendPose(bucket, model);

    // Bookkeeping of the cycle (in the phase the sample belonged to).
    if (static_cast<std::size_t>(cycle) < cycles.size()) {
      CycleRecord& c = cycles[static_cast<std::size_t>(cycle)];
      c.peak_fill = std::max(c.peak_fill, fillMass);
      // The wrench read now is the mean over the interval just run, in the phase the
      // operator had set for it (lastPhase).
      if (digging(lastPhase)) {
        c.dig_force_peak = std::max(c.dig_force_peak, force.norm());
        c.dig_force_sum += force.norm();
        ++c.dig_samples;
      }
      if (op.phase() != lastPhase) {
        if (op.phase() == ex::Phase::kDump) c.carried = fillMass;
        if (lastPhase == ex::Phase::kDump) c.after_dump = fillMass;
        if (lastPhase == ex::Phase::kSwingBack) {
          c.duration = t - cycleStart;
          cycleStart = t;
        }
      }
    }
    lastPhase = op.phase();
    const auto& act = model.actuators();
    for (std::size_t i = 0; i < 4; ++i) peakForce[i] = std::max(peakForce[i], std::abs(act[i].force));

    const auto& q = model.angles();
    const ex::Vec3 p = model.bucketPivot();
    csv << t << "," << cycle << "," << ex::phaseName(op.phase());
    for (double angle : q) csv << "," << angle * kRadToDeg;
    for (const auto& a : act) {
      csv << "," << a.valve << "," << a.length << "," << a.speed << "," << a.free_speed << "," << a.force << ","
          << a.dem_force << "," << a.load_ratio;
    }
    csv << "," << p.x() << "," << p.y() << "," << p.z() << "," << fillMass << "," << fill.count() << ","
        << force.x() << "," << force.y() << "," << force.z() << "," << torque.x() << "," << torque.y() << ","
        << torque.z() << "\n";
    if (t + 1e-9 >= nextLog) {
      nextLog += opt.log_interval_s;
      // Simulated seconds per wall second since the compile (the pit's settling is before it).
      const double wallSoFar = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
      std::printf(
          "excavator t %6.2f s  cycle %d %-14s fill %7.1f kg  force [kN] swing %6.1f boom %7.1f stick %7.1f bucket "
          "%7.1f  angles [deg] %6.1f %6.1f %7.1f %7.1f  |F_dem| %6.2f kN  real time x%.3f\n",
          t, cycle + 1, ex::phaseName(op.phase()), fillMass, act[0].force / 1e3, act[1].force / 1e3,
          act[2].force / 1e3, act[3].force / 1e3, q[0] * kRadToDeg, q[1] * kRadToDeg, q[2] * kRadToDeg,
          q[3] * kRadToDeg, force.norm() / 1e3, wallSoFar > 0.0 ? t / wallSoFar : 0.0);
      std::fflush(stdout);
    }
  }
  const double simulated = session.time();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
  if (!finishedEarly) session.finish(op.done() ? "excavator: all cycles done" : "excavator: stopped at --stop-at");
  csv.flush();

  std::ofstream summary(std::filesystem::path(opt.output) / "excavator_summary.txt");
  double dug = 0.0;
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    const CycleRecord& c = cycles[i];
    dug += c.carried - c.after_dump;
    const double digMean = c.dig_samples > 0 ? c.dig_force_sum / c.dig_samples : 0.0;  // [N]
    summary << "cycle_" << i + 1 << "_carried_kg = " << c.carried << "\ncycle_" << i + 1
            << "_after_dump_kg = " << c.after_dump << "\ncycle_" << i + 1 << "_peak_fill_kg = " << c.peak_fill
            << "\ncycle_" << i + 1 << "_duration_s = " << c.duration << "\ncycle_" << i + 1
            << "_dig_force_peak_N = " << c.dig_force_peak << "\ncycle_" << i + 1
            << "_dig_force_mean_N = " << digMean << "\n";
    std::printf("excavator cycle %zu: carried %.1f kg, left after dump %.1f kg, peak fill %.1f kg, %.2f s; "
                "digging force peak %.2f kN, mean %.2f kN\n",
                i + 1, c.carried, c.after_dump, c.peak_fill, c.duration, c.dig_force_peak / 1e3, digMean / 1e3);
  }
  summary << "mass_dumped_kg = " << dug << "\n";
  for (std::size_t i = 0; i < 4; ++i) {
    summary << "peak_force_" << model.spec().actuators[i].name << "_N = " << peakForce[i] << "\n";
  }
  const double realTimeFactor = wall > 0.0 ? simulated / wall : 0.0;
  summary << "phase_timeouts = " << op.timeouts() << "\nsimulated_s = " << simulated << "\nwall_s = " << wall
          << "\nreal_time_factor = " << realTimeFactor << "\nfinished_early = " << (finishedEarly ? 1 : 0) << "\n";
  std::printf("excavator: mass dumped %.1f kg; peak cylinder force boom %.1f kN, stick %.1f kN, bucket %.1f kN, "
              "swing torque %.1f kN m; %.2f s simulated in %.1f s wall after the compile (real-time factor %.3f)\n",
              dug, peakForce[1] / 1e3, peakForce[2] / 1e3, peakForce[3] / 1e3, peakForce[0] / 1e3, simulated, wall,
              realTimeFactor);
  std::printf("excavator: outputs in %s (excavator.csv, excavator_summary.txt, bucket.stl)\n", opt.output.c_str());
  if (finishedEarly) {
    std::fprintf(stderr, "excavator: the server ended the simulation early: %s\n",
                 session.finishedInfo().reason().c_str());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (const std::optional<int> exitCode = parse(argc, argv, options)) return *exitCode;
  try {
    return run(options);
  } catch (const dc::ServerError& e) {
    std::cerr << "excavator: server error: " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "excavator: " << e.what() << "\n";
  }
  return 1;
}
