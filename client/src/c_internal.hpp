#pragma once
/// Internals shared by the C ABI's translation units: the handle structs, the
/// exception-to-status translation and the generic-layout conversions.
///
/// Why a tag in each handle: C callers (and Modelica tools) pass void*; a tag checked on
/// every call turns a swapped client/package argument into DL_ERR_ARGUMENT, not a crash.
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "demlink/client/client.hpp"
#include "demlink/demlink_c.h"
#include "demlink/v1/protocol.pb.h"

namespace demlink::client::c_abi {

inline constexpr std::uint32_t kClientTag = 0xD1C11E47u;
inline constexpr std::uint32_t kPackageTag = 0xD1BA6A6Eu;

struct Package {
  std::uint32_t tag = kPackageTag;
  std::vector<long long> ints;
  std::vector<double> reals;
  std::vector<std::string> strings;
  mutable std::vector<const char*> string_views;  ///< dl_get_strings hands out these pointers
};

struct Client {
  std::uint32_t tag = kClientTag;
  Connection connection;
  std::unique_ptr<Session> session;
  double timeout_s = 30.0;
  int exchange_order = DL_ORDER_SEND_FIRST;  ///< of the typed exchange calls (dl_set_exchange_order)
  /// Components whose split-order first call of the sample has been made (the next call is the second).
  std::set<const Component*> split_sent;
  std::string address;  ///< host:port connected to
  std::string last_error;
  int server_code = 0;
  std::string server_field;
  std::string server_component;
};

/// A caller's mistake (argument or layout); becomes DL_ERR_ARGUMENT.
class ArgumentError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The client behind a handle, or nullptr when it is none.
Client* asClient(dl_client* handle);
const Client* asClient(const dl_client* handle);
Package* asPackage(dl_package* handle);
const Package* asPackage(const dl_package* handle);

/// Runs `body` and turns every exception into a status, recording its message.
template <class Body>
int guarded(dl_client* handle, Body&& body);

/// The session of a connected client (DL_ERR_STATE via StateError otherwise).
Session& sessionOf(Client& client);
/// The component behind a client-local handle.
Component& componentOf(Client& client, int component);

/// The bytes of an STL file on the client's computer (a CAD part sent to the server).
std::string readStlFile(const std::string& path);
/// A component built from a declare package (generic layout, demlink_c.h).
std::unique_ptr<Component> componentFromPackage(const Package& package);
/// A source's size distribution in the layout of dl_declare_particle_source (sizeKind 0 one
/// radius, 1 uniform, 2 linear, 3 normal, 4 discrete pairs); ArgumentError on a bad count.
void setSourceSizes(ParticleSource& source, int kind, const std::vector<double>& params);
/// The box's contact law (0 default, 1 Hertz-Mindlin, 2 linear spring-dashpot) and integrator
/// (0 default, 1 velocity Verlet, 2 explicit Euler); ArgumentError naming `where` otherwise.
void setContactAndIntegrator(v1::SimulationBox& box, long long contactModel, long long integrator,
                             const std::string& where);
/// Applies an input package's reals to the component.
void applyInputs(Component& component, const Package& package);
/// Writes the component's latest outputs in the output layout.
void writeOutputs(const Component& component, int handle, Package& package);

/// Records a failure on the client and returns its status.
int fail(Client& client, int status, const std::string& message);

template <class Body>
int guarded(dl_client* handle, Body&& body) {
  Client* client = asClient(handle);
  if (client == nullptr) return DL_ERR_ARGUMENT;
  client->last_error.clear();
  try {
    return body(*client);
  } catch (const ServerError& e) {
    client->server_code = static_cast<int>(e.code());
    client->server_field = e.field();
    client->server_component = e.component();
    return fail(*client, DL_ERR_SERVER, e.what());
  } catch (const TimeoutError& e) {
    return fail(*client, DL_ERR_TIMEOUT, e.what());
  } catch (const ConnectionError& e) {
    return fail(*client, DL_ERR_CONNECT, e.what());
  } catch (const StateError& e) {
    return fail(*client, DL_ERR_STATE, e.what());
  } catch (const ArgumentError& e) {
    return fail(*client, DL_ERR_ARGUMENT, e.what());
  } catch (const std::exception& e) {
    return fail(*client, DL_ERR_INTERNAL, std::string("internal error: ") + e.what());
  } catch (...) {
    return fail(*client, DL_ERR_INTERNAL, "internal error: unknown exception");
  }
}

}  // namespace demlink::client::c_abi
