/// The view's listener, thread and connection registry (contract in view_server.hpp).
#include "demlink/server/view/view_server.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <thread>
#include <vector>

#include "demlink/core/base/input_error.hpp"
#include "view_connection.hpp"

namespace demlink::server {

class ViewServer::Impl final : public ViewHost {
 public:
  Impl(ViewFeed& feed, ViewServerOptions options)
      : feed_(feed), options_(std::move(options)), acceptor_(io_), work_(asio::make_work_guard(io_)) {
    asio::error_code error;
    const asio::ip::address address = asio::ip::make_address(options_.address, error);
    if (error) throw core::InputError(options_.field, options_.address, "not an IP address");
    const asio::ip::tcp::endpoint endpoint(address, options_.port);
    acceptor_.open(endpoint.protocol(), error);
    if (!error) acceptor_.set_option(asio::ip::tcp::acceptor::reuse_address(true), error);
    if (!error) acceptor_.bind(endpoint, error);
    if (!error) acceptor_.listen(asio::socket_base::max_listen_connections, error);
    if (error) {
      throw core::InputError(options_.field, options_.address + ":" + std::to_string(options_.port),
                             "cannot listen: " + error.message());
    }
    port_ = acceptor_.local_endpoint().port();
    feed_.setNotify([this] {
      // At most one wake-up waits in the queue, however fast the simulation captures.
      if (!wake_pending_.exchange(true)) {
        asio::post(io_, [this] {
          wake_pending_.store(false);
          offerFrames();
        });
      }
    });
  }

  ~Impl() override { stop(); }

  void start() {
    accept();
    tick();
    thread_ = std::thread([this] { io_.run(); });
  }

  void stop() {
    if (!thread_.joinable()) return;
    asio::post(io_, [this] {
      asio::error_code ignored;
      acceptor_.close(ignored);
      heartbeat_.cancel();
      const std::vector<std::shared_ptr<ViewConnection>> open = std::move(connections_);
      connections_.clear();
      for (const auto& connection : open) connection->close();
      work_.reset();
    });
    thread_.join();
    feed_.setDemand(0.0, {});
  }

  ViewFeed& feed() override { return feed_; }
  const ViewServerOptions& options() const override { return options_; }
  void countFrame() override { frames_sent_.fetch_add(1, std::memory_order_relaxed); }

  void demandChanged() override {
    std::erase_if(connections_, [](const std::shared_ptr<ViewConnection>& c) { return !c->open(); });
    double rate = 0.0;
    CaptureFields fields;
    for (const auto& connection : connections_) {
      if (!connection->isViewer()) continue;
      rate = std::max(rate, connection->rate());
      fields.speed = fields.speed || connection->colour() == ColourField::kSpeed;
      fields.force = fields.force || connection->colour() == ColourField::kForce;
    }
    feed_.setDemand(rate, fields);
  }

  std::uint16_t port() const { return port_; }
  std::uint64_t framesSent() const { return frames_sent_.load(std::memory_order_relaxed); }

 private:
  void offerFrames() {
    const std::vector<std::shared_ptr<ViewConnection>> open = connections_;  // offerFrame may close one
    for (const auto& connection : open) connection->offerFrame();
  }

  /// Once a second, whether or not the followed simulation steps: the pages' lists of
  /// simulations show the others' progress even while the followed one waits.
  void tick() {
    heartbeat_.expires_after(std::chrono::seconds(1));
    heartbeat_.async_wait([this](const asio::error_code& error) {
      if (error) return;
      offerFrames();
      tick();
    });
  }

  void accept() {
    acceptor_.async_accept([this](const asio::error_code& error, asio::ip::tcp::socket socket) {
      if (error == asio::error::operation_aborted) return;
      if (!error) {
        std::erase_if(connections_, [](const std::shared_ptr<ViewConnection>& c) { return !c->open(); });
        auto connection = std::make_shared<ViewConnection>(*this, std::move(socket));
        if (connections_.size() >= options_.max_connections) {
          connection->refuseBusy();
        } else {
          connections_.push_back(connection);
          connection->start();
        }
      }
      accept();
    });
  }

  ViewFeed& feed_;
  ViewServerOptions options_;
  asio::io_context io_;
  asio::ip::tcp::acceptor acceptor_;
  asio::executor_work_guard<asio::io_context::executor_type> work_;
  asio::steady_timer heartbeat_{io_};
  std::vector<std::shared_ptr<ViewConnection>> connections_;
  std::atomic<bool> wake_pending_{false};
  std::atomic<std::uint64_t> frames_sent_{0};
  std::uint16_t port_ = 0;
  std::thread thread_;
};

ViewServer::ViewServer(ViewFeed& feed, ViewServerOptions options)
    : impl_(std::make_unique<Impl>(feed, std::move(options))) {}
ViewServer::~ViewServer() = default;
void ViewServer::start() { impl_->start(); }
void ViewServer::stop() { impl_->stop(); }
std::uint16_t ViewServer::port() const { return impl_->port(); }
std::uint64_t ViewServer::framesSent() const { return impl_->framesSent(); }

std::string ViewServer::url() const {
  const ViewServerOptions& options = impl_->options();
  std::string host = options.address;
  if (host == "0.0.0.0") host = "127.0.0.1";
  if (host.find(':') != std::string::npos) host = "[" + host + "]";
  return "http://" + host + ":" + std::to_string(impl_->port()) + "/";
}

void parseViewAddress(const std::string& text, const std::string& field, ViewServerOptions& options) {
  const std::size_t colon = text.rfind(':');
  const std::string portText = colon == std::string::npos ? text : text.substr(colon + 1);
  std::string address = colon == std::string::npos ? "127.0.0.1" : text.substr(0, colon);
  if (address.size() >= 2 && address.front() == '[' && address.back() == ']') {
    address = address.substr(1, address.size() - 2);
  }
  unsigned port = 0;
  const auto [end, error] = std::from_chars(portText.data(), portText.data() + portText.size(), port);
  if (portText.empty() || error != std::errc() || end != portText.data() + portText.size() || port > 65535) {
    throw core::InputError(field, text, "expected ADDRESS:PORT or PORT, with PORT in [0, 65535]");
  }
  asio::error_code parseError;
  asio::ip::make_address(address, parseError);
  if (address.empty() || parseError) throw core::InputError(field, text, "the address is not an IP address");
  options.address = address;
  options.port = static_cast<std::uint16_t>(port);
}

}  // namespace demlink::server
