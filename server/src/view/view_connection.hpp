#pragma once
/// One socket of the view server, from its HTTP request to, for /ws, a WebSocket that
/// sends frames. Everything runs on the server's one thread.
///
/// Page files: "/" (index.html) and the other files of server/web/ from the program,
/// "/three/..." from libjs-three's folder; each answered with "Connection: close".
/// /ws: the handshake (and the token, when one is set), then the scene JSON, a hello
/// naming the run's kind and frames, the list of a live server's simulations (again when
/// it changes, and every second for their times), and binary frames (frame_encoder.hpp)
/// whenever the feed has a newer snapshot, the page's rate allows one and its byte budget
/// covers it. Scene, list and frames are those of the simulation this page follows: the
/// feed's default until the page chooses one (sim=ID), and again when that one closes.
/// At most one write is in flight: a frame that cannot go now is not kept.
#include "demlink/server/net/asio.hpp"

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "demlink/server/view/frame_encoder.hpp"
#include "demlink/server/view/http_request.hpp"
#include "demlink/server/view/view_feed.hpp"
#include "demlink/server/view/view_server.hpp"
#include "demlink/server/view/websocket.hpp"

namespace demlink::server {

/// What a connection needs of its server.
class ViewHost {
 public:
  virtual ~ViewHost() = default;
  [[nodiscard]] virtual ViewFeed& feed() = 0;
  [[nodiscard]] virtual const ViewServerOptions& options() const = 0;
  /// A page's wishes changed (rate, colour) or it left: the feed's demand is recomputed.
  virtual void demandChanged() = 0;
  virtual void countFrame() = 0;
};

class ViewConnection : public std::enable_shared_from_this<ViewConnection> {
 public:
  ViewConnection(ViewHost& host, asio::ip::tcp::socket socket);

  void start();
  /// Refuses the connection with 503 (the server is at its connection cap) and closes.
  void refuseBusy();
  /// The feed has a new snapshot, or a second passed: send what this page is due.
  void offerFrame();
  void close();

  [[nodiscard]] bool open() const { return open_; }
  [[nodiscard]] bool isViewer() const { return websocket_; }
  [[nodiscard]] double rate() const { return rate_; }
  [[nodiscard]] ColourField colour() const { return request_.colour; }
  [[nodiscard]] SimulationId followed() const { return followed_; }

 private:
  using Clock = std::chrono::steady_clock;

  void readMore();
  void onRead(std::size_t bytes);
  void handleRequest(const HttpRequest& request);
  void serveFile(const HttpRequest& request);
  void respond(int status, const std::string& reason, std::string_view contentType, std::string_view body,
               bool headOnly);
  void startWebSocket(const HttpRequest& request);
  void onMessage(const ClientMessage& message);
  void sendText(std::string text);
  /// Queues one unfragmented message (text or control) behind the others.
  void sendControl(WebSocketOpcode opcode, std::string payload);
  /// Sends the feed's list of simulations; false when it has none.
  bool sendSimulations(Clock::time_point now);
  /// A live page whose simulation closed follows the default from now on; the list it is
  /// sent next says which that is, and that one's scene and frames follow.
  void leaveClosedSimulation();
  void writeNext();
  void writeRawThenClose(std::string bytes);
  /// Calls offerFrame() again after `seconds`, so a capture that came too early for this
  /// page's rate or byte budget (a run's last one, say) is still sent.
  void retryFrameAfter(double seconds);

  ViewHost& host_;
  asio::ip::tcp::socket socket_;
  asio::steady_timer request_timer_;
  asio::steady_timer retry_timer_;
  bool retry_armed_ = false;
  std::array<char, 4096> read_buffer_{};
  HttpRequestParser http_;
  WebSocketFrameParser frames_;
  bool open_ = true;
  bool websocket_ = false;
  bool writing_ = false;
  bool closing_ = false;  ///< a close frame or the last response is queued: close once written

  // The page's wishes.
  double rate_ = 10.0;
  FrameRequest request_;
  std::uint32_t wanted_frame_ = 0;  ///< recorded runs
  SimulationId followed_ = kDefaultSimulation;

  // Output: small text/control messages queue (bounded); a frame is only ever the latest.
  std::deque<std::string> pending_;
  std::string inflight_text_;
  FrameHeader frame_header_;
  std::vector<std::uint8_t> frame_;
  FrameScratch scratch_;
  std::uint64_t sent_version_ = 0;
  std::uint64_t sent_scene_version_ = 0;
  std::uint64_t sent_simulations_version_ = 0;
  std::uint64_t checked_simulations_version_ = 0;  ///< when leaveClosedSimulation() last looked
  Clock::time_point simulations_sent_{};
  Clock::time_point last_frame_{};
  double byte_allowance_ = 0.0;  ///< token bucket [B]
  Clock::time_point allowance_time_ = Clock::now();
};

}  // namespace demlink::server
