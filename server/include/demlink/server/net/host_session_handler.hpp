#pragma once
/// SessionHandler over a CoSimulationHost: plain forwarding.
///
/// Header-only on purpose: only the demlink-server executable (and the host fuzzer)
/// instantiates it, so the transport library and its tests never need the host's
/// implementation to link.
#include "demlink/server/cosim/co_simulation_host.hpp"
#include "demlink/server/net/session_handler.hpp"

namespace demlink::server {

class HostSessionHandler final : public SessionHandler {
 public:
  /// `host` must outlive this adapter.
  explicit HostSessionHandler(CoSimulationHost& host) : host_(host) {}

  std::vector<Outgoing> connected(ConnectionId id, const v1::Hello& hello, SteadyClock::time_point now) override {
    return host_.connected(id, hello, now);
  }
  std::vector<Outgoing> received(ConnectionId from, const v1::ClientMessage& message,
                                 SteadyClock::time_point now) override {
    return host_.received(from, message, now);
  }
  std::vector<Outgoing> disconnected(ConnectionId id, const std::string& why, SteadyClock::time_point now) override {
    return host_.disconnected(id, why, now);
  }
  std::vector<Outgoing> poll(SteadyClock::time_point now) override { return host_.poll(now); }
  [[nodiscard]] std::optional<SteadyClock::time_point> nextDeadline() const override { return host_.nextDeadline(); }
  std::vector<Outgoing> shutdown(const std::string& reason, SteadyClock::time_point now) override {
    return host_.shutdown(reason, now);
  }

 private:
  CoSimulationHost& host_;
};

}  // namespace demlink::server
