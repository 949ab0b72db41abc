/// Connection: framing, the write queue and the polite close (see connection.hpp).
#include "connection.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <string_view>
#include <utility>

#include "demlink/server/net/tcp_server.hpp"

namespace demlink::server {

v1::ServerMessage fatalError(v1::Error::Code code, const std::string& message, const std::string& field) {
  v1::ServerMessage out;
  v1::Error* error = out.mutable_error();
  error->set_code(code);
  error->set_message(message);
  error->set_field(field);
  error->set_fatal(true);
  return out;
}

Connection::Connection(TcpServer& server, asio::ip::tcp::socket socket, ConnectionId id, const Limits& limits)
    : server_(server),
      socket_(std::move(socket)),
      grace_timer_(socket_.get_executor()),
      hello_timer_(socket_.get_executor()),
      limits_(limits),
      id_(id),
      decoder_(std::min(limits.max_hello_frame_bytes, limits.max_frame_bytes)) {
  asio::error_code error;
  const asio::ip::tcp::endpoint remote = socket_.remote_endpoint(error);
  peer_ = error ? std::string("(unknown peer)") : remote.address().to_string() + ":" + std::to_string(remote.port());
  // Small frames (one DataPackage per exchange) must leave at once, not wait for Nagle.
  socket_.set_option(asio::ip::tcp::no_delay(true), error);
}

void Connection::start() {
  if (limits_.hello_timeout.count() > 0) {
    hello_timer_.expires_after(limits_.hello_timeout);
    hello_timer_.async_wait([self = shared_from_this()](const asio::error_code& error) {
      if (error || self->welcomed_ || !self->open_) return;
      const std::string what = "no Hello within " + std::to_string(self->limits_.hello_timeout.count()) +
                               " ms of connecting";
      spdlog::warn("connection {}: {}", self->id_, what);
      self->send(fatalError(v1::Error::TIMEOUT, what, "hello"));
      self->close(what);
    });
  }
  readMore();
}

void Connection::setWelcomed() {
  welcomed_ = true;
  hello_timer_.cancel();
  decoder_.setMaxFrameBytes(limits_.max_frame_bytes);
}

bool Connection::heldBack() const { return open_ && (outputBehind() || server_.handlerBusyWith(id_)); }

void Connection::resume() {
  if (!open_ || heldBack()) return;
  deliverFrames();
  readMore();
}

void Connection::readMore() {
  if (reading_ || read_done_ || socket_closed_ || heldBack()) return;
  reading_ = true;
  socket_.async_read_some(asio::buffer(read_buffer_),
                          [self = shared_from_this()](const asio::error_code& error, std::size_t bytes) {
                            self->reading_ = false;
                            self->onRead(error, bytes);
                          });
}

void Connection::onRead(const asio::error_code& error, std::size_t bytes) {
  if (error) {
    read_done_ = true;
    if (open_) {
      const std::size_t pending = decoder_.pendingBytes();
      if (error == asio::error::eof && pending > 0) {
        // The client may have shut down only its sending side: tell it what it cut off.
        const std::string what = "connection closed by the client with " + std::to_string(pending) +
                                 " bytes of an unfinished frame pending";
        send(fatalError(v1::Error::BAD_FRAME, what, "frame"));
        close("client closed the connection (" + std::to_string(pending) + " bytes of an unfinished frame pending)");
      } else if (error == asio::error::eof) {
        close("client closed the connection");
      } else {
        close("connection error: " + error.message());
      }
    }
    continueClosing();
    return;
  }
  // While closing, input is read only to be discarded (see the polite close).
  if (open_) {
    decoder_.feed(std::string_view(read_buffer_.data(), bytes));
    deliverFrames();
  }
  readMore();
}

void Connection::deliverFrames() {
  auto refuseFrame = [this](v1::Error::Code code, const std::string& what) {
    send(fatalError(code, what, "frame"));
    close("bad frame: " + what);
  };
  while (open_) {
    if (heldBack()) {
      // The rest waits in the decoder until the client takes its output (writeMore).
      if (!warned_behind_ && outputBehind()) {
        warned_behind_ = true;
        spdlog::warn("connection {}: {} bytes of output not taken by the client; its input waits until they are",
                     id_, queuedBytes());
      }
      return;
    }
    const std::optional<std::string> payload = decoder_.next();
    if (!payload) break;
    v1::ClientMessage message;
    if (!wire::parsePayload(*payload, message)) {
      refuseFrame(v1::Error::BAD_FRAME,
                  "payload of " + std::to_string(payload->size()) + " bytes is not a valid demlink.v1.ClientMessage");
      return;
    }
    if (message.message_case() == v1::ClientMessage::MESSAGE_NOT_SET) {
      refuseFrame(v1::Error::BAD_FRAME, "ClientMessage of " + std::to_string(payload->size()) +
                                            " bytes sets none of hello, declare, data, bye");
      return;
    }
    server_.onMessage(*this, message);
  }
  if (open_ && decoder_.error() != wire::FrameError::None) {
    refuseFrame(decoder_.error() == wire::FrameError::TooLarge ? v1::Error::FRAME_TOO_LARGE : v1::Error::BAD_FRAME,
                decoder_.errorMessage() + (welcomed_ || decoder_.error() != wire::FrameError::TooLarge
                                               ? std::string()
                                               : " allowed before Hello"));
  }
}

void Connection::send(const v1::ServerMessage& message) {
  if (!open_ || socket_closed_) return;
  wire::appendFrame(message, pending_);
  writeMore();
}

void Connection::writeMore() {
  if (writing_ || pending_.empty() || socket_closed_) return;
  inflight_.swap(pending_);
  pending_.clear();
  writing_ = true;
  asio::async_write(socket_, asio::buffer(inflight_),
                    [self = shared_from_this()](const asio::error_code& error, std::size_t /*bytes*/) {
                      self->writing_ = false;
                      self->inflight_.clear();
                      if (error) {
                        self->pending_.clear();
                        self->close("write failed: " + error.message());
                        self->closeSocket();
                        return;
                      }
                      self->writeMore();
                      if (self->open_ && !self->heldBack()) {
                        // Output drained below the cap: the held-back input goes on.
                        self->deliverFrames();
                        self->readMore();
                      }
                      self->continueClosing();
                    });
}

void Connection::close(const std::string& why) {
  if (!open_) return;
  const std::shared_ptr<Connection> self = shared_from_this();  // onGone drops the server's reference
  open_ = false;
  server_.onGone(*this, why);
  grace_timer_.expires_after(limits_.close_grace);
  grace_timer_.async_wait([self](const asio::error_code& error) {
    if (!error) self->closeSocket();
  });
  hello_timer_.cancel();
  readMore();  // a held-back connection drains its input while closing
  continueClosing();
}

void Connection::continueClosing() {
  if (open_ || socket_closed_ || writing_ || !pending_.empty()) return;
  if (!fin_sent_) {
    fin_sent_ = true;
    asio::error_code ignored;
    socket_.shutdown(asio::ip::tcp::socket::shutdown_send, ignored);
  }
  if (read_done_) closeSocket();
}

void Connection::closeSocket() {
  if (socket_closed_) return;
  socket_closed_ = true;
  grace_timer_.cancel();
  hello_timer_.cancel();
  asio::error_code ignored;
  socket_.close(ignored);
}

}  // namespace demlink::server
