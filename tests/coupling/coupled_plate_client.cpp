/// The coupled plate (coupled_plate.hpp) through the C++ client library: one connection
/// declares the scene of tests/fmu/plate_in_bed.cfg and calls Session::exchange() (send
/// first) every interval.
/// Usage: coupled_plate_client HOST PORT MASS DURATION INTERVAL. Prints the summary line;
/// exit 0, or 1 with the reason on stderr.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "coupled_plate.hpp"
#include "demlink/client/client.hpp"

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: %s HOST PORT MASS DURATION INTERVAL\n", argv[0]);
    return 2;
  }
  namespace client = demlink::client;
  const double mass = std::atof(argv[3]);
  const double duration = std::atof(argv[4]);
  const double h = std::atof(argv[5]);
  try {
    client::Connection connection;
    client::ConnectOptions options;
    options.client_name = "coupled_plate_client";
    options.timeout = std::chrono::milliseconds(300000);  // the bed settles before Compiled
    connection.connect(argv[1], static_cast<std::uint16_t>(std::atoi(argv[2])), options);
    client::Session session(connection);
    auto& box = session.add<client::SimulationBox>("box");
    box.setInitialGravity({0.0, 0.0, demlink::coupling::kGravity});
    box.setBounds({-0.2, -0.2, -0.05}, {0.2, 0.2, 0.4});
    box.setCommunicationInterval(h);
    session.add<client::Material>("gravel").setDatabaseName("gravel");
    session.add<client::Plane>("floor").setPoint({0.0, 0.0, 0.0}).setNormal({0.0, 0.0, 1.0}).setMaterial("gravel");
    session.add<client::PitGenerator>("bed")
        .setMaterial("gravel")
        .setBox({-0.08, -0.08, 0.0}, {0.08, 0.08, 0.1})
        .setRadiusRange(0.008, 0.01)
        .setTargetHeight(0.08)
        .setSeed(3);
    auto& plate = session.add<client::RigidBody>("plate");
    plate.setBox({0.06, 0.06, 0.01}).setMaterial("gravel").setMotion(client::RigidBodyMotion::kPredicted);
    plate.setInitialPose({0.0, 0.0, demlink::coupling::kStartHeight});
    plate.setCommunicationInterval(h);
    session.declare();
    session.declarationsDone();
    session.waitCompiled();
    const double timeStep = session.timeStep();

    demlink::coupling::CoupledPlate dynamics(mass);
    for (double t = 0.0; t < duration - 0.5 * h; t += h) {
      plate.setPose({0.0, 0.0, dynamics.height()}, {});
      plate.setVelocity({0.0, 0.0, dynamics.velocity()}, {});
      if (!session.exchange()) throw std::runtime_error("the server ended the run early");
      dynamics.advance(plate.meanForce().z, h);
    }
    dynamics.printSummary("cpp_client", h, timeStep);
    session.finish("coupled plate done");
  } catch (const std::exception& error) {
    std::fprintf(stderr, "coupled_plate_client: %s\n", error.what());
    return 1;
  }
  return 0;
}
