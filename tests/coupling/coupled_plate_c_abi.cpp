/// The coupled plate (coupled_plate.hpp) through the C ABI (libdemlink_c), in either of its
/// send-first orders:
///   send_first  one client declares the scene and calls dl_rigid_body_exchange once per
///               interval (DL_ORDER_SEND_FIRST, the default);
///   modelica    the Modelica package's sequence: one client per component, all driven from
///               this thread in DL_ORDER_SEND_FIRST_SPLIT; at each sample every exchanged
///               component's call sends the inputs at t, and a second pass (the event
///               iteration after it) returns the outputs of [t, t + h].
/// Usage: coupled_plate_c_abi HOST PORT MASS DURATION INTERVAL send_first|modelica.
/// Prints the summary line; exit 0, or 1 with the reason on stderr.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "coupled_plate.hpp"
#include "demlink/demlink_c.h"

namespace {

struct ClientDeleter {
  void operator()(dl_client* client) const { dl_client_destroy(client); }
};
using Client = std::unique_ptr<dl_client, ClientDeleter>;

void check(int status, const Client& client, const std::string& what) {
  if (status != DL_OK) {
    throw std::runtime_error(what + " failed (status " + std::to_string(status) + "): " + dl_last_error(client.get()));
  }
}

Client connectClient(const char* host, int port, const std::string& name, int order) {
  Client client(dl_client_create());
  if (!client) throw std::runtime_error("dl_client_create: out of memory");
  check(dl_set_timeout(client.get(), 300.0), client, "dl_set_timeout");  // the bed settles before Compiled
  check(dl_set_exchange_order(client.get(), order), client, "dl_set_exchange_order");
  check(dl_connect_to_host(client.get(), host, port, name.c_str(), nullptr), client, "dl_connect_to_host " + name);
  return client;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 7 || (std::strcmp(argv[6], "send_first") != 0 && std::strcmp(argv[6], "modelica") != 0)) {
    std::fprintf(stderr, "usage: %s HOST PORT MASS DURATION INTERVAL send_first|modelica\n", argv[0]);
    return 2;
  }
  const char* host = argv[1];
  const int port = std::atoi(argv[2]);
  const double mass = std::atof(argv[3]);
  const double duration = std::atof(argv[4]);
  const double h = std::atof(argv[5]);
  const bool modelica = std::strcmp(argv[6], "modelica") == 0;
  const int order = modelica ? DL_ORDER_SEND_FIRST_SPLIT : DL_ORDER_SEND_FIRST;
  try {
    // Modelica: one connection per component; send_first: all on one.
    std::vector<Client> clients;
    clients.reserve(5);  // the references below stay valid
    auto clientFor = [&](const std::string& name) -> Client& {
      if (modelica || clients.empty()) clients.push_back(connectClient(host, port, modelica ? name : "c_abi", order));
      return clients.back();
    };
    const double gravity[3] = {0.0, 0.0, demlink::coupling::kGravity};
    const double lower[3] = {-0.2, -0.2, -0.05};
    const double upper[3] = {0.2, 0.2, 0.4};
    int handle = -1;
    // The box is exchanged too under Modelica (its SimulationBox samples like every
    // component); one client's send-first call allows only one due component.
    Client& boxClient = clientFor("box");
    const int boxHandle = 0;
    check(dl_declare_simulation_box(boxClient.get(), "box", modelica ? h : 0.0, std::nan(""), 0.0, gravity, lower,
                                    upper, 0, &handle),
          boxClient, "dl_declare_simulation_box");
    Client& materialClient = clientFor("gravel");
    const double nan = std::nan("");
    check(dl_declare_material(materialClient.get(), "gravel", "gravel", nan, nan, nan, nan, nan, nan, &handle),
          materialClient, "dl_declare_material");
    Client& floorClient = clientFor("floor");
    const double origin[3] = {0.0, 0.0, 0.0};
    const double up[3] = {0.0, 0.0, 1.0};
    check(dl_declare_plane(floorClient.get(), "floor", origin, up, "gravel", &handle), floorClient, "dl_declare_plane");
    Client& bedClient = clientFor("bed");
    const double bedLower[3] = {-0.08, -0.08, 0.0};
    const double bedUpper[3] = {0.08, 0.08, 0.1};
    check(dl_declare_pit_generator(bedClient.get(), "bed", "gravel", bedLower, bedUpper, 0.008, 0.01, 0.08, 3, &handle),
          bedClient, "dl_declare_pit_generator");
    Client& plateClient = clientFor("plate");
    const double size[3] = {0.06, 0.06, 0.01};
    double pose[7] = {0.0, 0.0, demlink::coupling::kStartHeight, 1.0, 0.0, 0.0, 0.0};
    int plateHandle = -1;
    check(dl_declare_rigid_body_box(plateClient.get(), "plate", h, size, "gravel", pose, 1, &plateHandle), plateClient,
          "dl_declare_rigid_body_box");
    for (Client& c : clients) check(dl_declarations_done(c.get()), c, "dl_declarations_done");
    for (Client& c : clients) check(dl_wait_compiled(c.get()), c, "dl_wait_compiled");
    double timeStep = 0.0;
    check(dl_time_step(plateClient.get(), &timeStep), plateClient, "dl_time_step");

    demlink::coupling::CoupledPlate dynamics(mass);
    double twist[6] = {};
    double wrench[12] = {};
    double boxOut[4] = {};
    int particles = 0;
    for (double t = 0.0; t < duration - 0.5 * h; t += h) {
      pose[2] = dynamics.height();
      twist[2] = dynamics.velocity();
      const int passes = modelica ? 2 : 1;
      for (int pass = 0; pass < passes; ++pass) {  // in declaration order, as a Modelica tool calls them
        if (modelica) {
          check(dl_simulation_box_exchange(boxClient.get(), boxHandle, nullptr, boxOut, &particles), boxClient,
                "dl_simulation_box_exchange");
        }
        check(dl_rigid_body_exchange(plateClient.get(), plateHandle, pose, twist, wrench), plateClient,
              "dl_rigid_body_exchange");
      }
      dynamics.advance(wrench[2], h);
    }
    dynamics.printSummary(modelica ? "c_abi_modelica" : "c_abi_send_first", h, timeStep);
    for (Client& c : clients) check(dl_finish(c.get(), "coupled plate done"), c, "dl_finish");
    for (Client& c : clients) dl_wait_finished(c.get());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "coupled_plate_c_abi: %s\n", error.what());
    return 1;
  }
  return 0;
}
