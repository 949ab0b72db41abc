/// The C ABI's client: connection, generic send/receive, session calls. Every entry
/// point runs inside guarded(), which turns exceptions into status codes and keeps the
/// message per client.
#include <chrono>
#include <cmath>
#include <new>

#include "c_internal.hpp"

namespace demlink::client::c_abi {

Client* asClient(dl_client* handle) {
  auto* c = static_cast<Client*>(handle);
  return c != nullptr && c->tag == kClientTag ? c : nullptr;
}
const Client* asClient(const dl_client* handle) {
  const auto* c = static_cast<const Client*>(handle);
  return c != nullptr && c->tag == kClientTag ? c : nullptr;
}

int fail(Client& client, int status, const std::string& message) {
  try {
    client.last_error = message;
  } catch (...) {
    client.last_error.clear();  // out of memory: the status still says what kind of failure
  }
  return status;
}

Session& sessionOf(Client& client) {
  if (!client.session) throw StateError("not connected: call dl_connect_to_host first");
  return *client.session;
}

Component& componentOf(Client& client, int component) {
  Session& session = sessionOf(client);
  if (component < 0 || static_cast<std::size_t>(component) >= session.size()) {
    throw ArgumentError("component handle " + std::to_string(component) + " does not exist (this client has " +
                        std::to_string(session.size()) + " components)");
  }
  return session.component(static_cast<std::size_t>(component));
}

namespace {

int handleOf(Session& session, const Component* component) {
  for (std::size_t i = 0; i < session.size(); ++i) {
    if (&session.component(i) == component) return static_cast<int>(i);
  }
  return -1;
}

const char* text(const std::string& s) { return s.c_str(); }

}  // namespace
}  // namespace demlink::client::c_abi

using namespace demlink::client;
using namespace demlink::client::c_abi;

extern "C" {

const char* dl_version(void) { return DEMLINK_C_VERSION; }

dl_client* dl_client_create(void) { return new (std::nothrow) Client(); }

void dl_client_destroy(dl_client* client) {
  // Destroying closes the socket; it never throws (Connection's destructor only closes).
  delete asClient(client);
}

int dl_set_timeout(dl_client* client, double seconds) {
  return guarded(client, [&](Client& c) -> int {
    if (!(seconds > 0.0) || !std::isfinite(seconds)) {
      throw ArgumentError("timeout must be a positive number of seconds, got " + std::to_string(seconds));
    }
    c.timeout_s = seconds;
    c.connection.setTimeout(std::chrono::milliseconds(static_cast<long long>(std::ceil(seconds * 1000.0))));
    return DL_OK;
  });
}

int dl_connect_to_host(dl_client* client, const char* host, int port, const char* client_name, const char* token) {
  return guarded(client, [&](Client& c) -> int {
    if (host == nullptr) throw ArgumentError("host is NULL");
    if (port <= 0 || port > 65535) throw ArgumentError("port " + std::to_string(port) + " is not in 1..65535");
    ConnectOptions options;
    options.client_name = client_name != nullptr && client_name[0] != '\0' ? client_name : "demlink_c";
    options.access_token = token != nullptr ? token : "";
    const std::string address = std::string(host) + ":" + std::to_string(port);
    if (c.session) {
      // A tool that runs its initialisation twice connects again: same server, same name: nothing to do.
      if (c.address == address && c.connection.options().client_name == options.client_name &&
          c.connection.isOpen()) {
        return DL_OK;
      }
      throw StateError("already connected to " + c.address + " as '" + c.connection.options().client_name +
                       "'; a client connects once (create another client for " + address + ")");
    }
    options.timeout = std::chrono::milliseconds(static_cast<long long>(std::ceil(c.timeout_s * 1000.0)));
    c.connection.connect(host, static_cast<std::uint16_t>(port), options);
    c.session = std::make_unique<Session>(c.connection);
    c.address = address;
    return DL_OK;
  });
}

const char* dl_last_error(const dl_client* client) {
  const Client* c = asClient(client);
  return c == nullptr ? "invalid client handle" : text(c->last_error);
}

int dl_last_server_error_code(const dl_client* client) {
  const Client* c = asClient(client);
  return c == nullptr ? 0 : c->server_code;
}

const char* dl_last_server_error_field(const dl_client* client) {
  const Client* c = asClient(client);
  return c == nullptr ? "" : text(c->server_field);
}

const char* dl_last_server_error_component(const dl_client* client) {
  const Client* c = asClient(client);
  return c == nullptr ? "" : text(c->server_component);
}

int dl_set_exchange_order(dl_client* client, int order) {
  return guarded(client, [&](Client& c) -> int {
    if (order != DL_ORDER_SEND_FIRST && order != DL_ORDER_SEND_FIRST_SPLIT && order != DL_ORDER_RECEIVE_FIRST) {
      throw ArgumentError("exchange order " + std::to_string(order) +
                          " is none of DL_ORDER_SEND_FIRST (0), DL_ORDER_SEND_FIRST_SPLIT (1), DL_ORDER_RECEIVE_FIRST (2)");
    }
    if (c.session) {
      for (std::size_t i = 0; i < c.session->size(); ++i) {
        if (c.session->component(i).awaitingAnswer()) {
          throw StateError("dl_set_exchange_order: an answer is in flight; change the order between samples");
        }
      }
    }
    c.exchange_order = order;
    return DL_OK;
  });
}

int dl_send_package(dl_client* client, const dl_package* package) {
  return guarded(client, [&](Client& c) -> int {
    const Package* p = asPackage(package);
    if (p == nullptr) throw ArgumentError("invalid package handle");
    if (!p->strings.empty()) {  // a declaration; its layout is checked before the state
      std::unique_ptr<Component> component = componentFromPackage(*p);
      Session& session = sessionOf(c);
      std::size_t index = 0;
      session.declareOnce(std::move(component), index);  // a repeated identical declaration is a no-op
      return DL_OK;
    }
    Session& session = sessionOf(c);
    if (p->ints.empty()) throw ArgumentError("input package: ints[0] = component handle is required");
    if (p->ints[0] < 0 || p->ints[0] > INT32_MAX) throw ArgumentError("input package: bad component handle");
    Component& component = componentOf(c, static_cast<int>(p->ints[0]));
    session.waitCompiled();
    if (session.finished()) return fail(c, DL_ERR_FINISHED, "the simulation has finished: " + session.finishedInfo().reason());
    applyInputs(component, *p);
    session.send(component);
    return DL_OK;
  });
}

int dl_recv_package(dl_client* client, dl_package* package) {
  return guarded(client, [&](Client& c) -> int {
    Package* p = asPackage(package);
    if (p == nullptr) throw ArgumentError("invalid package handle");
    Session& session = sessionOf(c);
    session.waitCompiled();
    bool inFlight = false;
    for (std::size_t i = 0; i < session.size(); ++i) inFlight = inFlight || session.component(i).awaitingAnswer();
    if (session.finished()) return fail(c, DL_ERR_FINISHED, "the simulation has finished: " + session.finishedInfo().reason());
    if (!inFlight) throw StateError("dl_recv_package: no package in flight (send one first)");
    Component* answered = session.receiveAny();
    if (answered == nullptr) {
      return fail(c, DL_ERR_FINISHED, "the simulation has finished: " + session.finishedInfo().reason());
    }
    writeOutputs(*answered, handleOf(session, answered), *p);
    return DL_OK;
  });
}

int dl_get_outputs(dl_client* client, int component, dl_package* package) {
  return guarded(client, [&](Client& c) -> int {
    Package* p = asPackage(package);
    if (p == nullptr) throw ArgumentError("invalid package handle");
    writeOutputs(componentOf(c, component), component, *p);
    return DL_OK;
  });
}

int dl_declarations_done(dl_client* client) {
  return guarded(client, [&](Client& c) -> int {
    sessionOf(c).declarationsDone();
    return DL_OK;
  });
}

int dl_wait_compiled(dl_client* client) {
  return guarded(client, [&](Client& c) -> int {
    sessionOf(c).waitCompiled();
    return DL_OK;
  });
}

int dl_time_step(dl_client* client, double* seconds) {
  return guarded(client, [&](Client& c) -> int {
    if (seconds == nullptr) throw ArgumentError("seconds is NULL");
    *seconds = sessionOf(c).waitCompiled().time_step();
    return DL_OK;
  });
}

int dl_component_interval_steps(dl_client* client, int component, long long* steps) {
  return guarded(client, [&](Client& c) -> int {
    if (steps == nullptr) throw ArgumentError("steps is NULL");
    Component& target = componentOf(c, component);
    sessionOf(c).waitCompiled();
    *steps = static_cast<long long>(target.intervalSteps());
    return DL_OK;
  });
}

const char* dl_compile_report(const dl_client* client) {
  const Client* c = asClient(client);
  if (c == nullptr || !c->session) return "";
  return text(c->session->report().text());
}

int dl_finish(dl_client* client, const char* reason) {
  return guarded(client, [&](Client& c) -> int {
    sessionOf(c).sendBye(reason != nullptr && reason[0] != '\0' ? reason : "client finished");
    return DL_OK;
  });
}

int dl_wait_finished(dl_client* client) {
  return guarded(client, [&](Client& c) -> int {
    sessionOf(c).waitFinished();
    return DL_OK;
  });
}

const char* dl_finished_reason(const dl_client* client) {
  const Client* c = asClient(client);
  if (c == nullptr || !c->session || !c->session->finished()) return "";
  return text(c->session->finishedInfo().reason());
}

}  // extern "C"
