// Tutorial client (docs/tutorial.md): pour grains into a tray and weigh them.
// It declares the whole scene itself, holds the tray still, and at the end compares the
// force the grains exert on the tray with the weight of the grains a sensor counts in it.
// Usage: weigh_grains [--host H] [--port P] [--token T]; exit 0 when they agree within 3 %.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "demlink/client/client.hpp"

namespace dc = demlink::client;

int main(int argc, char** argv) {
  std::string host = "127.0.0.1";
  unsigned port = 47000;
  dc::ConnectOptions options;
  options.client_name = "weigh_grains";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--host") host = argv[i + 1];
    if (flag == "--port") port = static_cast<unsigned>(std::atoi(argv[i + 1]));
    if (flag == "--token") options.access_token = argv[i + 1];
  }
  constexpr double kInterval = 1e-3;  // communication interval [s]
  constexpr double kGravity = 9.81;   // [m/s^2]
  try {
    dc::Connection connection;
    connection.connect(host, static_cast<std::uint16_t>(port), options);
    dc::Session session(connection);

    auto& box = session.add<dc::SimulationBox>("box");
    box.setTimeStep(1e-5).setEndTime(0.8).setInitialGravity({0, 0, -kGravity});
    // 10 % instead of the default 1 %: trades restitution accuracy for speed (at 1 % these
    // grains (e = 0.3) need a step below 7.4e-6 s).
    box.setRestitutionTolerance(0.1);
    box.setBounds({-0.1, -0.1, -0.02}, {0.1, 0.1, 0.3}).setExpectedCount(6);
    session.add<dc::Material>("grain").setDensity(2500).setYoungsModulus(1e7).setPoissonRatio(0.3)
        .setRestitution(0.3).setSlidingFriction(0.5);
    session.add<dc::Plane>("floor").setNormal({0, 0, 1}).setMaterial("grain");

    // An open-top tray 8 x 8 x 4 cm whose centre is 5 cm above the floor.
    auto& tray = session.add<dc::RigidBody>("tray");
    tray.setBox({0.08, 0.08, 0.04}, /*openTop=*/true).setMaterial("grain").setInitialPose({0, 0, 0.05});
    tray.setMotion(dc::RigidBodyMotion::kPredicted);
    tray.setCommunicationInterval(kInterval);

    auto& source = session.add<dc::ParticleSource>("pour");
    source.setMaterial("grain").setRadius(0.004).setBox({0, 0, 0.12}, {0.025, 0.025, 0.01});
    source.setRateParticles(1000).setStopTime(0.1).setVelocity({0, 0, -0.5}).setSeed(1);

    auto& inside = session.add<dc::RegionSensor>("in_tray");
    inside.setBox({0, 0, 0}, {0.08, 0.08, 0.04}).attachTo("tray");  // in the tray's frame
    inside.setCommunicationInterval(kInterval);

    session.declare();
    session.waitCompiled();
    std::printf("%s", session.reportText().c_str());
    while (session.exchange()) {
      tray.setPose({0, 0, 0.05}, {});  // held still (the pose is re-sent anyway)
      tray.setVelocity({}, {});
      if (session.currentStep() % 10000 == 0) {  // every 0.1 s
        std::printf("t = %.3f s: %llu grains in the tray\n", session.time(),
                    static_cast<unsigned long long>(inside.count()));
      }
    }
    const double weight = inside.mass() * kGravity;
    const double force = -tray.meanForce().z;  // ON the tray BY the grains: downwards
    std::printf("%s at t = %.3f s: %llu grains, weight %.5f N, force on the tray %.5f N\n",
                session.finishedReason().c_str(), session.time(),
                static_cast<unsigned long long>(inside.count()), weight, force);
    session.finish();
    return inside.count() > 0 && std::abs(force - weight) < 0.03 * weight ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "weigh_grains: %s\n", error.what());
    return 1;
  }
}
