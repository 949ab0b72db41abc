#pragma once
/// The co-simulation server's TCP transport (standalone Asio, one thread).
///
/// Everything runs on one io_context thread because the SessionHandler is not thread-safe
/// and the world steps inside handler calls: a client's package is answered as soon as the
/// handler returns, with no locking and no hand-over between threads (round-trip latency).
///
/// The transport owns what the protocol needs before and around the handler: framing
/// (demlink::wire), the Hello check (version, access token), fatal framing errors
/// (BAD_FRAME / FRAME_TOO_LARGE) and closing connections politely (flush, FIN, drain).
/// Nothing a client sends can throw out of here: a handler exception becomes an INTERNAL
/// Error to that connection and the server keeps serving.
#include "demlink/server/net/asio.hpp"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "demlink/core/parallel/spin_wait.hpp"
#include "demlink/server/net/session_handler.hpp"
#include "demlink/wire/frame_codec.hpp"

namespace demlink::server {

class Connection;

struct TcpServerOptions {
  std::string listen_address = "127.0.0.1";  ///< loopback unless asked otherwise (security)
  std::uint16_t port = 0;                    ///< 0: an ephemeral port (see TcpServer::port())
  std::string access_token;                  ///< empty: Hello needs no token
  std::size_t max_frame_bytes = wire::kDefaultMaxFrameBytes;  ///< largest accepted payload [bytes]
  /// Largest payload before Hello passed [bytes]: a Hello is a few hundred bytes, and an
  /// unauthenticated peer must not make the server buffer max_frame_bytes.
  std::size_t max_hello_frame_bytes = 64u << 10;
  /// A connection that has not passed Hello this long after it was accepted gets TIMEOUT and
  /// is closed (slow or idle peers cannot hold sockets forever); zero: no limit.
  std::chrono::milliseconds hello_timeout{10000};
  /// Connections awaiting Hello at once; one more gets SERVER_BUSY and is closed [-].
  std::size_t max_unwelcomed = 64;
  /// Output queued for one connection above which its input is no longer read [bytes]:
  /// every answer follows a client's message, so a client that does not read stops being
  /// served, its memory stays bounded, and the host's client timeout ends it.
  std::size_t max_queued_bytes = 16u << 20;
  /// Checked after every handler call; true: flush everything, close and return from run()
  /// (demlink-server --once). Not called when empty.
  std::function<bool()> stop_when;
  /// A closing connection gets this long to take its last messages and hang up before it is
  /// closed hard (a client that never reads must not keep the server from stopping).
  std::chrono::milliseconds close_grace{2000};
  /// SIGINT/SIGTERM -> stop("SIGINT" / "SIGTERM"). For the executable; a process-wide
  /// setting, so tests leave it off.
  bool stop_on_signals = false;
  /// How long the network loop polls for the next event before it blocks in epoll_wait
  /// (core/parallel/spin_wait.hpp: spun only while a free CPU allows it); zero: block at once.
  /// A blocked loop takes tens of microseconds to wake, which dominates a short exchange.
  std::chrono::nanoseconds spin_wait = core::defaultSpinBudget();
};

class TcpServer {
 public:
  /// Binds and listens. Throws core::InputError naming the address for a bad address or a
  /// failed bind (e.g. port in use).
  TcpServer(SessionHandler& handler, TcpServerOptions options);
  ~TcpServer();
  TcpServer(const TcpServer&) = delete;
  TcpServer& operator=(const TcpServer&) = delete;

  /// The bound port (the ephemeral one when options.port was 0).
  [[nodiscard]] std::uint16_t port() const { return port_; }
  /// The bound address, e.g. "127.0.0.1".
  [[nodiscard]] std::string address() const;
  /// The server's io_context (e.g. for an asio::signal_set on the same thread).
  [[nodiscard]] asio::io_context& context() { return io_; }

  /// Serves until stop() or stop_when, then returns once every connection is flushed and closed.
  void run();
  /// Thread-safe: handler.shutdown(reason), send everything, close, make run() return.
  void stop(const std::string& reason);

 private:
  friend class Connection;  // reports messages and closes through the two calls below

  void onMessage(Connection& connection, const v1::ClientMessage& message);
  /// The handler holds this many of the connection's messages unanswered (a handler that
  /// works on other threads): its input waits, so a client cannot queue unbounded work.
  [[nodiscard]] bool handlerBusyWith(ConnectionId id) const;
  void onGone(Connection& connection, const std::string& why);

  void accept();
  void checkHello(Connection& connection, const v1::ClientMessage& message);
  /// Runs one handler call: dispatches its messages; an exception is logged and, when
  /// `blame` is a live connection, answered with a fatal INTERNAL error.
  void callHandler(ConnectionId blame, const char* what, const std::function<std::vector<Outgoing>()>& call);
  void dispatch(std::vector<Outgoing> messages);
  void rearmTimer();
  /// Stops accepting and closes every connection; `shutdownReason` set: tell the handler first.
  void finish(const std::string& why, const std::optional<std::string>& shutdownReason);
  /// Sends a fatal transport error and closes the connection.
  void refuse(Connection& connection, v1::Error::Code code, const std::string& message, const std::string& field);

  SessionHandler& handler_;
  TcpServerOptions options_;
  asio::io_context io_{1};
  asio::ip::tcp::acceptor acceptor_;
  asio::steady_timer poll_timer_;
  asio::steady_timer accept_retry_;
  std::optional<asio::signal_set> signals_;  ///< cancelled by finish(), so run() can return
  std::optional<SteadyClock::time_point> armed_deadline_;
  std::uint16_t port_ = 0;
  ConnectionId next_id_ = 1;
  bool finishing_ = false;
  std::unordered_map<ConnectionId, std::shared_ptr<Connection>> connections_;  ///< live ones only
};

}  // namespace demlink::server
