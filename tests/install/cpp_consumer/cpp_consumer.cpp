// Uses the installed C++ client with its own headers only (no generated protobuf headers):
// declares a free-falling grain and a sensor around it. Without arguments it only builds the
// declarations; with --host H --port P it runs them on a server and checks the sensor's
// readings against free fall: mass = rho pi d^3 / 6, z = z0 - g t^2 / 2, v_z = -g t.
// Exit 0 when all agree.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <numbers>
#include <string>

#include "demlink/client/client.hpp"

namespace dc = demlink::client;

int main(int argc, char** argv) {
  std::string host;
  unsigned port = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--host") host = argv[i + 1];
    if (flag == "--port") port = static_cast<unsigned>(std::atoi(argv[i + 1]));
  }
  constexpr double kGravity = 9.81;    // [m/s^2]
  constexpr double kDensity = 2500.0;  // [kg/m^3]
  constexpr double kDiameter = 0.01;   // [m]
  constexpr double kZ0 = 0.5;          // start height [m]
  constexpr double kTimeStep = 1e-5;   // [s]
  try {
    dc::Connection connection;
    dc::Session session(connection);
    auto& box = session.add<dc::SimulationBox>("box");
    box.setTimeStep(kTimeStep).setEndTime(0.1).setInitialGravity({0, 0, -kGravity});
    box.setBounds({-0.1, -0.1, 0.0}, {0.1, 0.1, 0.6});
    session.add<dc::Material>("glass").setDensity(kDensity).setYoungsModulus(1e7).setPoissonRatio(0.3)
        .setRestitution(0.5).setSlidingFriction(0.3);
    session.add<dc::SingleParticle>("grain").setMaterial("glass").setPosition({0, 0, kZ0}).setDiameter(kDiameter);
    auto& sensor = session.add<dc::RegionSensor>("around");
    sensor.setBox({0, 0, 0.3}, {0.2, 0.2, 0.6});
    sensor.setCommunicationInterval(0.02);
    std::printf("declared %zu components; the sensor is a %s\n", session.size(), sensor.kind().c_str());
    if (host.empty()) return sensor.kind() == "region_sensor" ? 0 : 1;

    dc::ConnectOptions options;
    options.client_name = "cpp_consumer";
    connection.connect(host, static_cast<std::uint16_t>(port), options);
    session.declarationsDone();
    session.waitCompiled();
    const double mass = kDensity * std::numbers::pi * std::pow(kDiameter, 3) / 6.0;
    int exchanges = 0;
    bool agree = true;
    while (session.exchange()) {
      const double t = session.time();
      const double z = kZ0 - 0.5 * kGravity * t * t;
      const double vz = -kGravity * t;
      // Semi-implicit Euler is off by g dt t / 2 in z (< 1e-5 m here) and exact in v.
      const bool ok = sensor.count() == 1 && std::abs(sensor.mass() - mass) < 1e-9 * mass &&
                      std::abs(sensor.centreOfMass().z - z) < 1e-5 && std::abs(sensor.meanVelocity().z - vz) < 1e-6;
      std::printf("t = %.3f s: count %llu, mass %.6e kg (%.6e), z %.6f m (%.6f), v_z %.6f m/s (%.6f)%s\n", t,
                  static_cast<unsigned long long>(sensor.count()), sensor.mass(), mass, sensor.centreOfMass().z, z,
                  sensor.meanVelocity().z, vz, ok ? "" : "  <- differs");
      agree = agree && ok;
      ++exchanges;
    }
    std::printf("finished: %s after %d exchanges\n", session.finishedReason().c_str(), exchanges);
    session.finish();
    return agree && exchanges == 5 ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "cpp_consumer: %s\n", error.what());
    return 1;
  }
}
