#pragma once
/// One client connection of the TcpServer: bytes in (frames -> ClientMessages), bytes out
/// (a write queue), and a polite close.
///
/// Why a polite close: closing a socket that still has unread input makes the kernel send
/// a reset, and a reset can destroy the Error we just wrote before the client reads it. So a
/// closing connection flushes its queue, sends FIN (shutdown of the send side), discards
/// whatever the client still sends until it hangs up, and is closed hard only after a grace
/// period. Never two writes at once: frames queue in `pending_` while `inflight_` is written.
#include "demlink/server/net/asio.hpp"

#include <array>
#include <chrono>
#include <cstddef>
#include <memory>
#include <string>

#include "demlink/server/net/session_handler.hpp"
#include "demlink/wire/frame_codec.hpp"

namespace demlink::server {

class TcpServer;

/// A fatal Error as the transport sends it.
[[nodiscard]] v1::ServerMessage fatalError(v1::Error::Code code, const std::string& message, const std::string& field);

class Connection : public std::enable_shared_from_this<Connection> {
 public:
  /// Limits of one connection (TcpServerOptions has their meaning and defaults).
  struct Limits {
    std::size_t max_frame_bytes = 0;        ///< after Hello [bytes]
    std::size_t max_hello_frame_bytes = 0;  ///< before Hello [bytes]
    std::size_t max_queued_bytes = 0;       ///< output above which input is not read [bytes]
    std::chrono::milliseconds hello_timeout{0};  ///< zero: none
    std::chrono::milliseconds close_grace{0};
  };

  Connection(TcpServer& server, asio::ip::tcp::socket socket, ConnectionId id, const Limits& limits);

  /// Starts reading (and the Hello timeout); messages go to TcpServer::onMessage until the
  /// connection is gone.
  void start();
  /// Queues one message (dropped once the connection is closing).
  void send(const v1::ServerMessage& message);
  /// Ends the connection for the protocol (TcpServer::onGone(why), once) and closes it
  /// after the queued messages are sent.
  void close(const std::string& why);

  [[nodiscard]] ConnectionId id() const { return id_; }
  [[nodiscard]] const std::string& peer() const { return peer_; }
  /// Passed Hello and was handed to the SessionHandler.
  [[nodiscard]] bool welcomed() const { return welcomed_; }
  /// Passed Hello: the full frame cap applies and the Hello timeout stops.
  void setWelcomed();
  [[nodiscard]] bool open() const { return open_; }
  /// Input held back goes on if nothing holds it any more (the handler has answered).
  void resume();

 private:
  void readMore();
  void onRead(const asio::error_code& error, std::size_t bytes);
  void deliverFrames();
  void writeMore();
  /// Output queued and in flight [bytes].
  [[nodiscard]] std::size_t queuedBytes() const { return pending_.size() + inflight_.size(); }
  /// The client does not take its output (back-pressure).
  [[nodiscard]] bool outputBehind() const { return queuedBytes() > limits_.max_queued_bytes; }
  /// Input is held back while the client does not take its output, or while the handler
  /// still works on this connection's earlier messages (TcpServer::handlerBusyWith).
  [[nodiscard]] bool heldBack() const;
  /// Closing: FIN once the queue is empty, the socket once the client hung up too.
  void continueClosing();
  void closeSocket();

  TcpServer& server_;
  asio::ip::tcp::socket socket_;
  asio::steady_timer grace_timer_;
  asio::steady_timer hello_timer_;
  Limits limits_;
  ConnectionId id_;
  std::string peer_;
  wire::FrameDecoder decoder_;
  std::array<char, 64 * 1024> read_buffer_{};
  std::string pending_;   ///< frames queued while a write is in flight
  std::string inflight_;  ///< the frames being written
  bool writing_ = false;
  bool reading_ = false;      ///< a read is outstanding
  bool warned_behind_ = false;  ///< the first hold-back was logged
  bool welcomed_ = false;
  bool open_ = true;        ///< messages are delivered and accepted
  bool read_done_ = false;  ///< the client hung up (EOF or error)
  bool fin_sent_ = false;
  bool socket_closed_ = false;
};

}  // namespace demlink::server
