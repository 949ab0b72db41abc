#pragma once
/// One TCP connection to a demlink-server: Hello/Welcome, then framed ClientMessages out and
/// ServerMessages in, every blocking call bounded by a timeout.
///
/// Why blocking: a system model drives the coupling from its own solver loop (a Modelica
/// sample() event, a test, a script) and has nothing else to do while the server computes
/// the next interval, so a call that returns the answer is the simplest correct API.
/// Internally each call runs Asio's io_context for at most the timeout (the run_for idiom),
/// so a silent or dead server turns into a TimeoutError instead of a hang.
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "demlink/client/types.hpp"

namespace demlink::client {

struct ConnectOptions {
  std::string client_name = "demlink-client";  ///< shown in the server's logs and errors
  std::string access_token;                    ///< the server's --token, if it requires one
  /// Hello.simulation: connections naming the same simulation are assembled together;
  /// while one is being assembled the server refuses a client naming another.
  std::string simulation;
  /// Bound of every blocking call (connect, send, one receive) [ms]. It must exceed the
  /// longest time the server may need to simulate one interval plus the time the slowest
  /// other client takes to send its package.
  std::chrono::milliseconds timeout{30000};
  std::size_t max_frame_bytes = 64u << 20;  ///< largest accepted ServerMessage [bytes]
  /// How long a receive polls the socket before it blocks [us]: a blocked thread takes
  /// tens of microseconds to wake, which dominates a short exchange. Spun only while a
  /// free CPU allows it (docs/benchmarks.md, "Waits"); 0: block at once. Unset: 50 us, or
  /// DEMLINK_SPIN_WAIT_US from the environment (as for the C ABI).
  std::optional<std::chrono::microseconds> spin_wait;
};

class Connection {
 public:
  Connection();
  ~Connection();
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  /// Connects, sends Hello and waits for Welcome. Throws ConnectionError (refused, name
  /// not resolved), TimeoutError, or ServerError (wrong token or protocol version).
  const v1::Welcome& connect(const std::string& host, std::uint16_t port, const ConnectOptions& options = {});

  /// Sends one message (blocking until the bytes are handed to the socket, bounded by the
  /// timeout).
  void send(const v1::ClientMessage& message);

  /// The next ServerMessage. An Error message is thrown as ServerError; when it is fatal,
  /// the Finished the server sends after it is read first (within a short grace) and kept
  /// as finishedAfterError(), then the connection is closed. Nothing arriving within the
  /// timeout is a TimeoutError.
  [[nodiscard]] v1::ServerMessage receive();
  /// The Finished that followed the last fatal Error (reason, step, output directory);
  /// nullptr when none did.
  [[nodiscard]] const v1::Finished* finishedAfterError() const { return finished_after_error_.get(); }

  /// Closes the socket (idempotent). A later send/receive throws ConnectionError.
  void close();
  [[nodiscard]] bool isOpen() const;
  [[nodiscard]] const v1::Welcome& welcome() const { return *welcome_; }
  [[nodiscard]] const ConnectOptions& options() const { return options_; }
  void setTimeout(std::chrono::milliseconds timeout) { options_.timeout = timeout; }

 private:
  /// How long receive() waits for the Finished that follows a fatal Error.
  static constexpr std::chrono::milliseconds kFinishedGrace{2000};
  /// One framed message, Errors included (no interpretation).
  v1::ServerMessage readMessage(std::chrono::milliseconds timeout);

  ProtoPtr<v1::Finished> finished_after_error_;
  struct Impl;  // Asio lives only in the .cpp: clients of this header need no Asio
  std::unique_ptr<Impl> impl_;
  ConnectOptions options_;
  std::chrono::nanoseconds spin_budget_{0};  ///< the receive's spin (options_.spin_wait resolved)
  ProtoPtr<v1::Welcome> welcome_;
};

}  // namespace demlink::client
