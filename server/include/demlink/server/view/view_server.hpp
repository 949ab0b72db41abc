#pragma once
/// The live view's web server: one page (HTML and JavaScript built into the program),
/// three.js from Debian's libjs-three, and a WebSocket (/ws) that streams binary frames
/// (frame_encoder.hpp) from a ViewFeed. It runs on a thread and io_context of its own, so
/// it never shares a thread with stepping or with the co-simulation's network.
///
/// Safe by default (docs/server.md, "Live view"): it binds 127.0.0.1 unless told
/// otherwise; with an access token set, /ws needs "?token=" (compared in constant time);
/// it is read-only (a page can ask for a rate, a particle budget, a colour field, which of
/// a live server's simulations it follows, and a recorded frame, nothing else); connections, frame rate, bytes per second and request
/// sizes are capped; each connection has at most one frame in flight and a frame that is
/// not due or over the byte budget is skipped, never queued.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "demlink/server/view/view_feed.hpp"

namespace demlink::server {

struct ViewServerOptions {
  std::string address = "127.0.0.1";
  std::uint16_t port = 0;  ///< 0: any free port (port() tells which)
  /// Required as "?token=" on /ws when not empty.
  std::string access_token;
  /// Where libjs-three installs three.js; served under /three/.
  std::filesystem::path three_root = "/usr/share/javascript/three";
  std::size_t max_connections = 8;          ///< open sockets, pages and file requests together [-]
  double max_frame_rate = 30.0;             ///< highest rate a page may ask for [1/s]
  double max_bytes_per_second = 64.0e6;     ///< per connection [B/s]
  double request_timeout = 10.0;            ///< to receive a request's header block [s]
  std::string field = "--view";             ///< how errors name the option that configured this server
};

class ViewServer {
 public:
  /// Binds the listening socket (throws core::InputError naming options.field when the
  /// address is malformed or the port cannot be bound); serving starts with start().
  ViewServer(ViewFeed& feed, ViewServerOptions options);
  ~ViewServer();
  ViewServer(const ViewServer&) = delete;
  ViewServer& operator=(const ViewServer&) = delete;

  /// Starts the server's thread.
  void start();
  /// Closes every connection and joins the thread (also done by the destructor).
  void stop();

  [[nodiscard]] std::uint16_t port() const;
  /// The page's address, e.g. "http://127.0.0.1:8080/"; with a token set the page needs
  /// "?token=..." appended, which is never printed or logged here.
  [[nodiscard]] std::string url() const;

  /// Frames sent so far, over all connections [-] (tests, logs).
  [[nodiscard]] std::uint64_t framesSent() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

/// Splits "ADDR:PORT" (or just "PORT", meaning 127.0.0.1) into options.address and
/// options.port; throws core::InputError naming `field` for anything else.
void parseViewAddress(const std::string& text, const std::string& field, ViewServerOptions& options);

}  // namespace demlink::server
