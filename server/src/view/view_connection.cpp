/// One view connection (contract in view_connection.hpp).
#include "view_connection.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "demlink/server/net/same_token.hpp"
#include "demlink/server/view/web_assets.hpp"
#include "json_text.hpp"
#include "view_requests.hpp"

namespace demlink::server {
namespace {

/// Largest three.js file served [B] (three.module.js is ~1.2 MB).
constexpr std::uintmax_t kMaxServedFileBytes = 8u << 20;
/// Text and control messages a page may have waiting (its errors, pongs) [-].
constexpr std::size_t kMaxPendingMessages = 16;
/// A page's list of simulations is sent again at least this often, for their times [s].
constexpr double kSimulationsInterval = 1.0;

std::string_view contentType(std::string_view name) {
  if (name.ends_with(".html")) return "text/html; charset=utf-8";
  if (name.ends_with(".js")) return "text/javascript; charset=utf-8";
  if (name.ends_with(".css")) return "text/css; charset=utf-8";
  if (name.ends_with(".json")) return "application/json";
  return "application/octet-stream";
}

std::string_view statusText(int status) {
  switch (status) {
    case 200:
      return "OK";
    case 400:
      return "Bad Request";
    case 403:
      return "Forbidden";
    case 404:
      return "Not Found";
    case 405:
      return "Method Not Allowed";
    case 414:
      return "URI Too Long";
    case 431:
      return "Request Header Fields Too Large";
    case 503:
      return "Service Unavailable";
    case 505:
      return "HTTP Version Not Supported";
    default:
      return "Error";
  }
}

/// A path under /three/ that names a .js file without leaving the folder.
bool safeThreePath(std::string_view relative) {
  if (relative.empty() || relative.size() > 200 || !relative.ends_with(".js")) return false;
  if (relative.find("..") != std::string_view::npos || relative.front() == '/') return false;
  return std::all_of(relative.begin(), relative.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '/' || c == '.' || c == '_' || c == '-';
  });
}

std::string helloJson(ViewFeed& feed, double maxRate) {
  std::string times;
  const std::uint32_t frames = feed.frameCount();
  for (std::uint32_t k = 0; k < frames; ++k) {
    if (k > 0) times += ',';
    times += jsonNumber(feed.frameTime(k));
  }
  return fmt::format(R"({{"kind":"hello","live":{},"frames":{},"times":[{}],"maxRate":{}}})",
                     frames == 0 ? "true" : "false", frames, times, maxRate);
}

}  // namespace

ViewConnection::ViewConnection(ViewHost& host, asio::ip::tcp::socket socket)
    : host_(host),
      socket_(std::move(socket)),
      request_timer_(socket_.get_executor()),
      retry_timer_(socket_.get_executor()) {}

void ViewConnection::start() {
  request_timer_.expires_after(std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(host_.options().request_timeout)));
  request_timer_.async_wait([self = shared_from_this()](const asio::error_code& error) {
    if (!error && !self->websocket_) self->close();
  });
  readMore();
}

void ViewConnection::refuseBusy() {
  open_ = true;
  const std::string body = "the view serves at most " + std::to_string(host_.options().max_connections) +
                           " connections at once\n";
  writeRawThenClose(fmt::format("HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain\r\nContent-Length: "
                                "{}\r\nConnection: close\r\nRetry-After: 5\r\n\r\n{}",
                                body.size(), body));
}

void ViewConnection::readMore() {
  socket_.async_read_some(asio::buffer(read_buffer_),
                          [self = shared_from_this()](const asio::error_code& error, std::size_t bytes) {
                            if (error) {
                              self->close();
                              return;
                            }
                            self->onRead(bytes);
                          });
}

void ViewConnection::onRead(std::size_t bytes) {
  if (!open_) return;
  const std::string_view data(read_buffer_.data(), bytes);
  if (!websocket_) {
    if (closing_) {  // the response is on its way; ignore anything after the request
      readMore();
      return;
    }
    switch (http_.feed(data)) {
      case HttpRequestParser::State::kIncomplete:
        readMore();
        return;
      case HttpRequestParser::State::kError:
        respond(http_.errorStatus(), http_.errorReason(), "text/plain", http_.errorReason() + "\n", false);
        return;
      case HttpRequestParser::State::kComplete:
        handleRequest(http_.request());
        if (websocket_ && !http_.leftover().empty()) frames_.feed(http_.leftover());
        break;
    }
  } else {
    frames_.feed(data);
  }
  if (websocket_) {
    while (std::optional<ClientMessage> message = frames_.next()) onMessage(*message);
    if (frames_.failed()) {
      std::string payload;
      payload += static_cast<char>(frames_.closeCode() >> 8);
      payload += static_cast<char>(frames_.closeCode() & 0xFF);
      payload += frames_.failure();
      sendControl(WebSocketOpcode::kClose, payload);
      closing_ = true;
      return;
    }
  }
  readMore();
}

void ViewConnection::handleRequest(const HttpRequest& request) {
  if (request.path == "/ws") {
    startWebSocket(request);
    return;
  }
  serveFile(request);
}

void ViewConnection::serveFile(const HttpRequest& request) {
  const bool headOnly = request.method == "HEAD";
  const std::string name = request.path == "/" ? "index.html" : request.path.substr(1);
  for (const WebAsset& asset : webAssets()) {
    if (asset.name == name) {
      respond(200, "", contentType(name), asset.bytes, headOnly);
      return;
    }
  }
  constexpr std::string_view kThree = "three/";
  if (name.starts_with(kThree) && safeThreePath(std::string_view(name).substr(kThree.size()))) {
    const std::filesystem::path file = host_.options().three_root / name.substr(kThree.size());
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(file, error);
    if (!error && size <= kMaxServedFileBytes) {
      std::ifstream in(file, std::ios::binary);
      std::ostringstream bytes;
      bytes << in.rdbuf();
      if (in) {
        respond(200, "", contentType(name), bytes.str(), headOnly);
        return;
      }
    }
  }
  respond(404, "not found", "text/plain", "not found: " + std::string(request.path.substr(0, 200)) + "\n", headOnly);
}

void ViewConnection::respond(int status, const std::string& reason, std::string_view contentTypeText,
                             std::string_view body, bool headOnly) {
  if (status != 200) spdlog::debug("view: {} {}", status, reason);
  std::string response = fmt::format(
      "HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nCache-Control: no-cache\r\n"
      "X-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n",
      status, statusText(status), contentTypeText, body.size());
  if (!headOnly) response += body;
  writeRawThenClose(std::move(response));
}

void ViewConnection::startWebSocket(const HttpRequest& request) {
  if (const std::optional<std::string> error = websocketHandshakeError(request)) {
    respond(400, *error, "text/plain", *error + "\n", false);
    return;
  }
  const std::string& token = host_.options().access_token;
  if (!token.empty()) {
    const auto given = request.query.find("token");
    if (given == request.query.end() || !sameToken(token, given->second)) {
      // The token itself is never echoed or logged.
      respond(403, "wrong or missing token", "text/plain", "this view needs the server's access token (?token=)\n",
              false);
      return;
    }
  }
  websocket_ = true;
  request_timer_.cancel();
  pending_.push_back(websocketHandshakeResponse(request));
  sent_scene_version_ = host_.feed().sceneVersion(followed_);
  sendText(host_.feed().sceneJson(followed_));
  sendText(helloJson(host_.feed(), host_.options().max_frame_rate));
  sendSimulations(Clock::now());
  host_.demandChanged();
  writeNext();
}

void ViewConnection::onMessage(const ClientMessage& message) {
  switch (message.opcode) {
    case WebSocketOpcode::kClose:
      sendControl(WebSocketOpcode::kClose, message.payload.substr(0, 2));
      closing_ = true;
      return;
    case WebSocketOpcode::kPing:
      sendControl(WebSocketOpcode::kPong, message.payload);
      return;
    case WebSocketOpcode::kText: {
      std::string error;
      const std::optional<ViewRequest> request =
          parseViewRequest(message.payload, host_.options().max_frame_rate, error);
      if (!request) {
        sendText(R"({"kind":"error","message":)" + jsonString(error) + "}");
        return;
      }
      bool demand = false;
      if (request->rate) {
        rate_ = *request->rate;
        demand = true;
      }
      if (request->max_particles) request_.max_particles = *request->max_particles;
      if (request->colour) {
        request_.colour = *request->colour;
        demand = true;
      }
      if (request->frame) wanted_frame_ = *request->frame;
      if (request->simulation) {
        if (const std::optional<std::string> why = host_.feed().cannotFollow(*request->simulation)) {
          sendText(R"({"kind":"error","message":)" +
                   jsonString("sim = \"" + std::to_string(*request->simulation) + "\": " + *why) + "}");
        } else if (*request->simulation != followed_) {
          followed_ = *request->simulation;
          sent_simulations_version_ = 0;  // the page's list says which it follows now
          demand = true;
        }
      }
      // A changed request shows on the next frame, even if the snapshot is the same.
      sent_version_ = 0;
      if (demand) host_.demandChanged();
      offerFrame();
      return;
    }
    default:
      return;  // pongs and binary messages carry nothing for the view
  }
}

void ViewConnection::sendText(std::string text) {
  if (!text.empty()) sendControl(WebSocketOpcode::kText, std::move(text));
}

void ViewConnection::sendControl(WebSocketOpcode opcode, std::string payload) {
  if (!open_ || closing_) return;
  if (pending_.size() >= kMaxPendingMessages) {
    close();  // a page that takes no data but keeps asking is dropped
    return;
  }
  const FrameHeader header = encodeServerFrameHeader(opcode, payload.size());
  pending_.push_back(std::string(reinterpret_cast<const char*>(header.bytes.data()), header.size) + payload);
  writeNext();
}

void ViewConnection::offerFrame() {
  if (!open_ || !websocket_ || closing_) return;
  leaveClosedSimulation();
  if (writing_) return;
  const Clock::time_point now = Clock::now();
  const double since = std::chrono::duration<double>(now - last_frame_).count();
  // 0.9: captures arrive on the feed's clock, so allow a little early rather than skip one.
  ViewFeed& feed = host_.feed();
  const bool live = feed.frameCount() == 0;
  if (live && since < 0.9 / rate_) {
    retryFrameAfter(1.0 / rate_ - since);
    return;
  }
  const double cap = host_.options().max_bytes_per_second;
  byte_allowance_ = std::min(cap, byte_allowance_ + cap * std::chrono::duration<double>(now - allowance_time_).count());
  allowance_time_ = now;
  if (byte_allowance_ < 0.0) {
    retryFrameAfter(-byte_allowance_ / cap);
    return;
  }
  // Another simulation (the page chose one, or a server's next): its scene first.
  if (const std::uint64_t sceneVersion = feed.sceneVersion(followed_); sceneVersion != sent_scene_version_) {
    sent_scene_version_ = sceneVersion;
    sendText(feed.sceneJson(followed_));
    return;
  }
  if (live && (feed.simulationsVersion() != sent_simulations_version_ ||
               std::chrono::duration<double>(now - simulations_sent_).count() >= kSimulationsInterval)) {
    if (sendSimulations(now)) return;
  }
  // A recorded frame already sent (or refused) is not read again until the page asks anew.
  if (!live && sent_version_ == std::uint64_t{wanted_frame_} + 1) return;
  std::uint64_t version = 0;
  const ViewSnapshot* snapshot = nullptr;
  try {
    snapshot = feed.snapshot(followed_, wanted_frame_, version);
  } catch (const std::exception& error) {  // a recorded frame's file is unreadable
    sent_version_ = std::uint64_t{wanted_frame_} + 1;  // not again until the page asks anew
    sendText(R"({"kind":"error","message":)" + jsonString(error.what()) + "}");
    return;
  }
  if (snapshot == nullptr || version == sent_version_) return;
  request_.frame_index = live ? 0 : static_cast<std::uint32_t>(version - 1);
  request_.frame_count = feed.frameCount();
  encodeFrame(*snapshot, request_, scratch_, frame_);
  frame_header_ = encodeServerFrameHeader(WebSocketOpcode::kBinary, frame_.size());
  byte_allowance_ -= static_cast<double>(frame_.size());
  sent_version_ = version;
  last_frame_ = now;
  writing_ = true;
  host_.countFrame();
  const std::array<asio::const_buffer, 2> buffers{asio::buffer(frame_header_.bytes.data(), frame_header_.size),
                                                   asio::buffer(frame_)};
  asio::async_write(socket_, buffers, [self = shared_from_this()](const asio::error_code& error, std::size_t) {
    self->writing_ = false;
    if (error) {
      self->close();
      return;
    }
    self->writeNext();
  });
}

void ViewConnection::leaveClosedSimulation() {
  if (followed_ == kDefaultSimulation) return;
  ViewFeed& feed = host_.feed();
  const std::uint64_t version = feed.simulationsVersion();
  if (version == checked_simulations_version_) return;
  checked_simulations_version_ = version;
  if (!feed.cannotFollow(followed_)) return;
  followed_ = kDefaultSimulation;
  sent_simulations_version_ = 0;
  sent_version_ = 0;
  host_.demandChanged();
}

bool ViewConnection::sendSimulations(Clock::time_point now) {
  ViewFeed& feed = host_.feed();
  sent_simulations_version_ = feed.simulationsVersion();
  simulations_sent_ = now;
  std::string list = feed.simulationsJson(followed_);
  if (list.empty()) return false;
  sendText(std::move(list));
  return true;
}

void ViewConnection::retryFrameAfter(double seconds) {
  if (retry_armed_) return;
  retry_armed_ = true;
  retry_timer_.expires_after(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds)));
  retry_timer_.async_wait([self = shared_from_this()](const asio::error_code& error) {
    self->retry_armed_ = false;
    if (!error) self->offerFrame();
  });
}

void ViewConnection::writeNext() {
  if (!open_ || writing_) return;
  if (pending_.empty()) {
    if (closing_) {
      close();
      return;
    }
    offerFrame();
    return;
  }
  inflight_text_ = std::move(pending_.front());
  pending_.pop_front();
  writing_ = true;
  asio::async_write(socket_, asio::buffer(inflight_text_),
                    [self = shared_from_this()](const asio::error_code& error, std::size_t) {
                      self->writing_ = false;
                      if (error) {
                        self->close();
                        return;
                      }
                      self->writeNext();
                    });
}

void ViewConnection::writeRawThenClose(std::string bytes) {
  pending_.push_back(std::move(bytes));
  closing_ = true;
  writeNext();
}

void ViewConnection::close() {
  if (!open_) return;
  open_ = false;
  asio::error_code ignored;
  request_timer_.cancel();
  retry_timer_.cancel();
  socket_.shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
  socket_.close(ignored);
  if (websocket_) host_.demandChanged();
}

}  // namespace demlink::server
