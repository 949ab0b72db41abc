#pragma once
/// What the network layer drives: the protocol behind the sockets, and the types both sides
/// share (connection ids, the clock, the messages to send).
///
/// The transport owns this interface and knows nothing else of the co-simulation: the
/// co-simulation host implements it, the transport is testable with a scripted fake
/// (tests/net) and the host with no sockets at all.
///
/// Contract the transport keeps:
/// - connected() only after a valid Hello (protocol version and access token checked).
/// - received() only for connections that passed connected(), and only for messages with
///   their oneof set (Hello included: a second Hello is the handler's to refuse).
/// - every id given to connected() gets exactly one disconnected() when its socket closes,
///   whatever the reason (EOF, reset, bad frame, close_after, stop); the handler must
///   tolerate it for ids it already forgot.
/// - all calls come from one thread (the server's io_context), never concurrently.
/// - a handler whose work finishes on threads of its own (SimulationHub: each simulation
///   steps on its own thread) hands the results back through the LoopPoster it was given
///   (attachLoop): the work runs on the network thread and what it returns is sent there.
/// - an Outgoing for an id that is already closed is dropped.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "demlink/v1/protocol.pb.h"

namespace demlink::server {

/// A connection, numbered by the transport from 1 in accept order.
using ConnectionId = std::uint64_t;
/// The clock of every deadline (quiet period, client timeout).
using SteadyClock = std::chrono::steady_clock;

/// One message for the transport to send.
struct Outgoing {
  ConnectionId to = 0;
  v1::ServerMessage message;
  bool close_after = false;  ///< close the connection once this message is sent
};

/// Runs a piece of work on the network thread and sends the messages it returns; callable
/// from any thread (it only queues the work).
using LoopPoster = std::function<void(std::function<std::vector<Outgoing>()>)>;

class SessionHandler {
 public:
  virtual ~SessionHandler() = default;

  /// The transport's poster, given once it can serve, and an empty function before it goes
  /// away (work posted after that is dropped). Handlers that answer only from their calls
  /// ignore it.
  virtual void attachLoop(LoopPoster /*poster*/) {}

  /// A connection passed Hello: normally Welcome, or an Error with close_after.
  virtual std::vector<Outgoing> connected(ConnectionId id, const v1::Hello& hello, SteadyClock::time_point now) = 0;
  /// Any later message of a connected connection.
  virtual std::vector<Outgoing> received(ConnectionId from, const v1::ClientMessage& message,
                                         SteadyClock::time_point now) = 0;
  /// Messages of this connection taken and not yet answered (work on other threads); the
  /// transport reads no more from it while there are too many. Handlers that answer in
  /// their calls have none.
  [[nodiscard]] virtual std::size_t pendingCalls(ConnectionId /*id*/) const { return 0; }
  /// The connection is gone; `why` is for logs and for the other clients.
  virtual std::vector<Outgoing> disconnected(ConnectionId id, const std::string& why,
                                             SteadyClock::time_point now) = 0;
  /// Called when nextDeadline() has passed.
  virtual std::vector<Outgoing> poll(SteadyClock::time_point now) = 0;
  /// When poll() next has something to do; nullopt: nothing scheduled.
  [[nodiscard]] virtual std::optional<SteadyClock::time_point> nextDeadline() const = 0;
  /// The server is stopping (signal): last messages before every connection closes.
  virtual std::vector<Outgoing> shutdown(const std::string& reason, SteadyClock::time_point now) = 0;
};

}  // namespace demlink::server
