/// Blocking Connection over standalone Asio with a bound on every call: each operation
/// is started asynchronously and io_context::run_for() waits at most the remaining time;
/// an operation still pending then is cancelled by closing the socket (the only portable
/// way to abort a pending read), so the connection is unusable after a timeout.
#include "demlink/client/connection.hpp"

#if !defined(_WIN32)
#include <sys/socket.h>
#include <sys/types.h>
#endif

#include <array>
#include <cerrno>
#include <cstring>
#include <string_view>

#include <asio.hpp>

#include "demlink/core/step/spin_history.hpp"
#include "demlink/core/step/spin_wait.hpp"
#include "demlink/v1/protocol.pb.h"
#include "demlink/wire/frame_codec.hpp"

namespace demlink::client {

ServerError::ServerError(const v1::Error& error)
    : std::runtime_error("server error " + v1::Error::Code_Name(error.code()) + ": " + error.message() +
                         (error.component().empty() ? "" : " (component '" + error.component() + "')") +
                         (error.field().empty() ? "" : " (field " + error.field() + ")")),
      code_(error.code()),
      message_(error.message()),
      component_(error.component()),
      field_(error.field()),
      fatal_(error.fatal()) {}

v1::Vector3 toProto(const Vec3& v) {
  v1::Vector3 out;
  out.set_x(v.x);
  out.set_y(v.y);
  out.set_z(v.z);
  return out;
}

v1::Quaternion toProto(const Quat& q) {
  v1::Quaternion out;
  out.set_w(q.w);
  out.set_x(q.x);
  out.set_y(q.y);
  out.set_z(q.z);
  return out;
}

Vec3 fromProto(const v1::Vector3& v) { return {v.x(), v.y(), v.z()}; }

Quat fromProto(const v1::Quaternion& q, bool present) {
  if (!present) return {};
  return {q.w(), q.x(), q.y(), q.z()};
}

struct Connection::Impl {
  asio::io_context io;
  asio::ip::tcp::socket socket{io};
  wire::FrameDecoder decoder;
  std::array<char, 64 * 1024> buffer{};
  std::string frame;  ///< the frame being sent (its capacity kept between sends)
  bool open = false;
  core::SpinHistory spin_history;  ///< the receive's recent waits

  explicit Impl(std::size_t maxFrame) : decoder(maxFrame) {}

  /// What a read that does not block found.
  enum class Read { kNothing, kBytes, kEnd };
  /// Reads what the socket holds now, without blocking, into the decoder. kEnd: end of
  /// stream or an error, which the blocking read then reports.
  Read readNow() {
#if defined(_WIN32)
    // Winsock has no per-call MSG_DONTWAIT: the socket is non-blocking (connect), which
    // leaves Asio's asynchronous operations as they are.
    std::error_code ec;
    const std::size_t got = socket.read_some(asio::buffer(buffer), ec);
    if (ec == asio::error::would_block || ec == asio::error::try_again || ec == asio::error::interrupted) {
      return Read::kNothing;
    }
    if (ec || got == 0) return Read::kEnd;
    decoder.feed(std::string_view(buffer.data(), got));
    return Read::kBytes;
#else
    const ssize_t n = ::recv(socket.native_handle(), buffer.data(), buffer.size(), MSG_DONTWAIT);
    if (n > 0) {
      decoder.feed(std::string_view(buffer.data(), static_cast<std::size_t>(n)));
      return Read::kBytes;
    }
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return Read::kNothing;
    return Read::kEnd;
#endif
  }

  /// Sends what the socket takes now without blocking, from `offset` of the frame; the
  /// new offset. Throws ConnectionError on a socket error.
  std::size_t sendNow(std::size_t offset) {
    while (offset < frame.size()) {
#if defined(_WIN32)
      std::error_code ec;
      const std::size_t n = socket.write_some(asio::buffer(frame.data() + offset, frame.size() - offset), ec);
      if (ec == asio::error::would_block || ec == asio::error::try_again) break;
      if (ec == asio::error::interrupted) continue;
      if (ec || n == 0) {
        const std::string why = ec ? ec.message() : "nothing sent";
        closeSocket();
        throw ConnectionError("send failed: " + why);
      }
      offset += n;
#else
      const ssize_t n = ::send(socket.native_handle(), frame.data() + offset, frame.size() - offset,
                               MSG_DONTWAIT | MSG_NOSIGNAL);
      if (n > 0) {
        offset += static_cast<std::size_t>(n);
      } else if (n < 0 && errno == EINTR) {
        continue;
      } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
        break;
      } else {
        const std::string why = n < 0 ? std::strerror(errno) : "nothing sent";
        closeSocket();
        throw ConnectionError("send failed: " + why);
      }
#endif
    }
    return offset;
  }

  /// Runs the pending operation for at most `timeout`; on expiry closes the socket, lets
  /// the cancelled handler run, and throws.
  void runFor(std::chrono::steady_clock::duration timeout, const char* what) {
    io.restart();
    io.run_for(timeout);
    if (!io.stopped()) {
      closeSocket();
      io.restart();
      io.run();
      throw TimeoutError(std::string("no ") + what + " within the timeout");
    }
  }

  void closeSocket() {
    // An open connection is one exchange party of the spin gate (spin_wait.hpp).
    if (open) core::SpinGate::instance().addExchangeParty(-1);
    std::error_code ignored;
    socket.shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
    socket.close(ignored);
    open = false;
  }
};

Connection::Connection() : welcome_(new v1::Welcome()) {}
Connection::~Connection() { close(); }

const v1::Welcome& Connection::connect(const std::string& host, std::uint16_t port, const ConnectOptions& options) {
  if (impl_ && impl_->open) throw StateError("Connection::connect: already connected");
  options_ = options;
  spin_budget_ = std::min<std::chrono::nanoseconds>(
      options.spin_wait ? std::chrono::nanoseconds(*options.spin_wait) : core::defaultSpinBudget(), core::kMaxSpinBudget);
  impl_ = std::make_unique<Impl>(options.max_frame_bytes);

  asio::ip::tcp::resolver resolver(impl_->io);
  std::error_code ec;
  const auto endpoints = resolver.resolve(host, std::to_string(port), ec);
  if (ec) throw ConnectionError("cannot resolve host '" + host + "': " + ec.message());

  std::error_code connectError = asio::error::would_block;
  asio::async_connect(impl_->socket, endpoints,
                      [&](const std::error_code& e, const asio::ip::tcp::endpoint&) { connectError = e; });
  impl_->runFor(options_.timeout, "connection");
  if (connectError) {
    impl_->closeSocket();
    throw ConnectionError("cannot connect to " + host + ":" + std::to_string(port) + ": " + connectError.message());
  }
  impl_->open = true;
  core::SpinGate::instance().addExchangeParty(1);
  // Small packages every interval: Nagle's algorithm would delay each by up to 40 ms.
  impl_->socket.set_option(asio::ip::tcp::no_delay(true), ec);
#if defined(_WIN32)
  impl_->socket.non_blocking(true, ec);  // readNow and sendNow never block (above)
#endif

  v1::ClientMessage hello;
  hello.mutable_hello()->set_protocol_version(v1::PROTOCOL_VERSION_CURRENT);
  hello.mutable_hello()->set_client_name(options_.client_name);
  hello.mutable_hello()->set_access_token(options_.access_token);
  hello.mutable_hello()->set_simulation(options_.simulation);
  send(hello);
  v1::ServerMessage answer = receive();
  if (!answer.has_welcome()) {
    close();
    throw ConnectionError("expected Welcome after Hello, got message case " +
                          std::to_string(static_cast<int>(answer.message_case())));
  }
  *welcome_ = answer.welcome();
  return *welcome_;
}

void Connection::send(const v1::ClientMessage& message) {
  if (!isOpen()) throw ConnectionError("send on a closed connection");
  impl_->frame.clear();
  wire::appendFrame(message, impl_->frame);
  // A package fits the socket's buffer: one non-blocking send, no reactor. The rest, if
  // the buffer is full, is written through Asio within the timeout.
  const std::size_t sent = impl_->sendNow(0);
  if (sent == impl_->frame.size()) return;
  std::error_code writeError = asio::error::would_block;
  asio::async_write(impl_->socket, asio::buffer(impl_->frame.data() + sent, impl_->frame.size() - sent),
                    [&](const std::error_code& e, std::size_t) { writeError = e; });
  impl_->runFor(options_.timeout, "send completion");
  if (writeError) {
    impl_->closeSocket();
    throw ConnectionError("send failed: " + writeError.message());
  }
}

v1::ServerMessage Connection::receive() {
  if (!impl_) throw ConnectionError("receive on a connection that was never opened");
  v1::ServerMessage message = readMessage(options_.timeout);
  if (message.has_error()) {
    if (message.error().fatal()) {
      // The server follows a fatal Error with Finished (the output directory, the reason),
      // then closes. Read it within a short grace so the caller can still learn where the
      // simulation's results are; anything else (or nothing) is not an error here.
      try {
        v1::ServerMessage next = readMessage(std::min<std::chrono::milliseconds>(options_.timeout, kFinishedGrace));
        if (next.has_finished()) finished_after_error_.reset(new v1::Finished(next.finished()));
      } catch (const std::exception&) {
      }
      impl_->closeSocket();
    }
    throw ServerError(message.error());
  }
  if (message.has_finished()) finished_after_error_.reset();
  return message;
}

v1::ServerMessage Connection::readMessage(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    // A frame may already be buffered (several messages can arrive in one read).
    if (std::optional<std::string> payload = impl_->decoder.next()) {
      v1::ServerMessage message;
      if (!wire::parsePayload(*payload, message)) {
        impl_->closeSocket();
        throw ConnectionError("the server sent a frame that is not a ServerMessage");
      }
      return message;
    }
    if (impl_->decoder.error() != wire::FrameError::None) {
      impl_->closeSocket();
      throw ConnectionError("bad frame from the server: " + impl_->decoder.errorMessage());
    }
    if (!impl_->open) throw ConnectionError("receive on a closed connection");
    // Spin-then-block (spin_history.hpp): read without blocking for a short while when
    // the recent waits say the answer comes soon, then block in the reactor.
    Impl::Read now = Impl::Read::kNothing;
    if (core::spinFor(impl_->spin_history, core::SpinGate::Party::kExchange, spin_budget_, [&] {
          now = impl_->readNow();
          return now != Impl::Read::kNothing;
        }) &&
        now == Impl::Read::kBytes) {
      continue;
    }
    std::error_code readError = asio::error::would_block;
    std::size_t received = 0;
    impl_->socket.async_read_some(asio::buffer(impl_->buffer), [&](const std::error_code& e, std::size_t n) {
      readError = e;
      received = n;
    });
    impl_->runFor(std::max(deadline - std::chrono::steady_clock::now(), std::chrono::steady_clock::duration::zero()),
                  "message from the server");
    impl_->spin_history.arrived(core::SpinHistory::Clock::now(), false);
    if (readError) {
      impl_->closeSocket();
      if (readError == asio::error::eof) throw ConnectionError("the server closed the connection");
      throw ConnectionError("receive failed: " + readError.message());
    }
    impl_->decoder.feed(std::string_view(impl_->buffer.data(), received));
  }
}

void Connection::close() {
  if (impl_) impl_->closeSocket();
}

bool Connection::isOpen() const { return impl_ && impl_->open; }

}  // namespace demlink::client
