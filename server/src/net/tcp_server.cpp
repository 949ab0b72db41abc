/// TcpServer: accepting, the Hello check, handler calls and the poll timer (see tcp_server.hpp).
#include "demlink/server/net/tcp_server.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <csignal>
#include <exception>
#include <utility>

#include "connection.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/log_text.hpp"
#include "demlink/core/parallel/spin_history.hpp"
#include "demlink/server/net/same_token.hpp"

namespace demlink::server {
namespace {

/// Messages of one connection the handler may hold unanswered before its input waits [-]:
/// enough for a client that sends every component's package of a step at once, few
/// enough that what they cost stays bounded.
constexpr std::size_t kMaxPendingCalls = 64;

std::string messageName(const v1::ClientMessage& message) {
  const google::protobuf::FieldDescriptor* field =
      v1::ClientMessage::descriptor()->FindFieldByNumber(static_cast<int>(message.message_case()));
  return field != nullptr ? field->name() : std::string("(none)");
}

}  // namespace

TcpServer::TcpServer(SessionHandler& handler, TcpServerOptions options)
    : handler_(handler), options_(std::move(options)), acceptor_(io_), poll_timer_(io_), accept_retry_(io_) {
  const std::string where = options_.listen_address + ":" + std::to_string(options_.port);
  asio::error_code error;
  const asio::ip::address address = asio::ip::make_address(options_.listen_address, error);
  if (error) throw core::InputError("listen address", options_.listen_address, "not an IP address");
  const asio::ip::tcp::endpoint endpoint(address, options_.port);
  // reuse_address: a restarted server can bind at once while old connections sit in TIME_WAIT.
  acceptor_.open(endpoint.protocol(), error);
  if (!error) acceptor_.set_option(asio::ip::tcp::acceptor::reuse_address(true), error);
  if (!error) acceptor_.bind(endpoint, error);
  if (!error) acceptor_.listen(asio::socket_base::max_listen_connections, error);
  if (error) throw core::InputError("listen address", where, "cannot listen: " + error.message());
  port_ = acceptor_.local_endpoint().port();
  if (options_.stop_on_signals) {
    signals_.emplace(io_, SIGINT, SIGTERM);
    signals_->async_wait([this](const asio::error_code& waitError, int signal) {
      if (!waitError) finish("server stopping: " + std::string(signal == SIGINT ? "SIGINT" : "SIGTERM"),
                             signal == SIGINT ? "SIGINT" : "SIGTERM");
    });
  }
  accept();
  rearmTimer();
  handler_.attachLoop([this](std::function<std::vector<Outgoing>()> work) {
    asio::post(io_, [this, work = std::move(work)] {
      if (finishing_) return;
      callHandler(0, "posted work", work);
      // The handler has answered something: input it held back may go on. Copied: a
      // resumed connection may close and leave the map.
      std::vector<std::shared_ptr<Connection>> open;
      open.reserve(connections_.size());
      for (const auto& entry : connections_) open.push_back(entry.second);
      for (const std::shared_ptr<Connection>& connection : open) connection->resume();
    });
  });
}

TcpServer::~TcpServer() { handler_.attachLoop({}); }

std::string TcpServer::address() const {
  asio::error_code error;
  const asio::ip::tcp::endpoint local = acceptor_.local_endpoint(error);
  return error ? options_.listen_address : local.address().to_string();
}

void TcpServer::run() {
  const std::chrono::nanoseconds budget = options_.spin_wait;
  if (budget.count() <= 0) {
    io_.run();
    return;
  }
  // Spin-then-block: handlers that are ready run at once; otherwise the loop polls
  // (non-blocking epoll) within the budget, then blocks for the next event. The loop is
  // one exchange party of the spin gate while it runs.
  core::SpinGate& gate = core::SpinGate::instance();
  gate.addExchangeParty(1);
  gate.addServerLoop(1);
  struct Leave {
    core::SpinGate& gate;
    ~Leave() {
      gate.addServerLoop(-1);
      gate.addExchangeParty(-1);
    }
  } leave{gate};
  // Whether a wait spins follows the loop's recent waits (SpinHistory): a loop that took
  // longer than the budget over a package (its client has blocked since) or whose clients
  // are paced far beyond the budget blocks at once.
  core::SpinHistory history;
  while (!io_.stopped()) {
    if (io_.poll() > 0) continue;
    if (io_.stopped()) break;
    if (core::spinFor(history, core::SpinGate::Party::kExchange, budget,
                      [this] { return io_.poll_one() > 0 || io_.stopped(); })) {
      continue;
    }
    io_.run_one();
    history.arrived(core::SpinHistory::Clock::now(), false);
  }
}

void TcpServer::stop(const std::string& reason) {
  asio::post(io_, [this, reason] { finish("server stopping: " + reason, reason); });
}

void TcpServer::accept() {
  acceptor_.async_accept([this](const asio::error_code& error, asio::ip::tcp::socket socket) {
    if (finishing_ || error == asio::error::operation_aborted) return;
    if (error) {
      // E.g. out of file descriptors: retry a little later instead of spinning.
      spdlog::warn("accept failed: {}", error.message());
      accept_retry_.expires_after(std::chrono::milliseconds(100));
      accept_retry_.async_wait([this](const asio::error_code& waitError) {
        if (!waitError && !finishing_) accept();
      });
      return;
    }
    const ConnectionId id = next_id_++;
    const Connection::Limits limits{options_.max_frame_bytes, options_.max_hello_frame_bytes,
                                    options_.max_queued_bytes, options_.hello_timeout, options_.close_grace};
    auto connection = std::make_shared<Connection>(*this, std::move(socket), id, limits);
    const auto unwelcomed = static_cast<std::size_t>(
        std::count_if(connections_.begin(), connections_.end(), [](const auto& entry) { return !entry.second->welcomed(); }));
    if (unwelcomed >= options_.max_unwelcomed) {
      // Refused before it is served: it never reaches the handler or the connection table.
      const std::string what = "too many connections awaiting Hello (" + std::to_string(unwelcomed) +
                               "); connect again later";
      spdlog::warn("connection {} from {}: {}", id, connection->peer(), what);
      connection->send(fatalError(v1::Error::SERVER_BUSY, what, "connection"));
      connection->close(what);
      accept();
      return;
    }
    spdlog::info("connection {} from {}", id, connection->peer());
    connections_.emplace(id, connection);
    connection->start();
    accept();
  });
}

bool TcpServer::handlerBusyWith(ConnectionId id) const {
  return handler_.pendingCalls(id) >= kMaxPendingCalls;
}

void TcpServer::onMessage(Connection& connection, const v1::ClientMessage& message) {
  if (!connection.welcomed()) {
    checkHello(connection, message);
    return;
  }
  const ConnectionId id = connection.id();
  callHandler(id, "received", [&] { return handler_.received(id, message, SteadyClock::now()); });
}

void TcpServer::checkHello(Connection& connection, const v1::ClientMessage& message) {
  if (!message.has_hello()) {
    refuse(connection, v1::Error::OUT_OF_ORDER, "the first message must be hello, got " + messageName(message),
           "message");
    return;
  }
  const v1::Hello& hello = message.hello();
  if (hello.protocol_version() != v1::PROTOCOL_VERSION_CURRENT) {
    refuse(connection, v1::Error::PROTOCOL_VERSION,
           "protocol version " + std::to_string(hello.protocol_version()) + " is not supported; this server speaks " +
               std::to_string(static_cast<int>(v1::PROTOCOL_VERSION_CURRENT)),
           "hello.protocol_version");
    return;
  }
  if (!options_.access_token.empty() && !sameToken(options_.access_token, hello.access_token())) {
    // The token itself is never echoed or logged.
    refuse(connection, v1::Error::ACCESS_DENIED,
           hello.access_token().empty() ? "this server requires an access token" : "wrong access token",
           "hello.access_token");
    return;
  }
  connection.setWelcomed();
  spdlog::info("connection {}: hello from {}", connection.id(), demlink::core::quotedLogText(hello.client_name()));
  const ConnectionId id = connection.id();
  callHandler(id, "connected", [&] { return handler_.connected(id, hello, SteadyClock::now()); });
}

void TcpServer::refuse(Connection& connection, v1::Error::Code code, const std::string& message,
                       const std::string& field) {
  spdlog::warn("connection {}: {} ({})", connection.id(), message, v1::Error::Code_Name(code));
  connection.send(fatalError(code, message, field));
  connection.close(message);
}

void TcpServer::onGone(Connection& connection, const std::string& why) {
  const ConnectionId id = connection.id();
  connections_.erase(id);
  spdlog::info("connection {} closed: {}", id, why);
  if (connection.welcomed()) {
    callHandler(0, "disconnected", [&] { return handler_.disconnected(id, why, SteadyClock::now()); });
  }
}

void TcpServer::callHandler(ConnectionId blame, const char* what,
                            const std::function<std::vector<Outgoing>()>& call) {
  std::string failure;
  try {
    dispatch(call());
  } catch (const std::exception& error) {
    failure = error.what();
  } catch (...) {
    failure = "unknown exception";
  }
  if (!failure.empty()) {
    spdlog::error("internal error in {} (connection {}): {}", what, blame, failure);
    const auto found = connections_.find(blame);
    if (found != connections_.end()) {
      const std::shared_ptr<Connection> connection = found->second;
      connection->send(fatalError(v1::Error::INTERNAL, std::string("internal error in ") + what + ": " + failure, ""));
      connection->close(std::string("internal error: ") + failure);
    }
  }
  rearmTimer();
  if (!finishing_ && options_.stop_when && options_.stop_when()) {
    // Posted: the messages just queued are written first, and no handler call is on the stack.
    asio::post(io_, [this] { finish("server finishing (its simulation ended)", std::nullopt); });
  }
}

void TcpServer::dispatch(std::vector<Outgoing> messages) {
  for (Outgoing& outgoing : messages) {
    const auto found = connections_.find(outgoing.to);
    if (found == connections_.end()) {
      spdlog::debug("dropping a message for closed connection {}", outgoing.to);
      continue;
    }
    const std::shared_ptr<Connection> connection = found->second;  // close() may erase the map entry
    connection->send(outgoing.message);
    if (outgoing.close_after) {
      connection->close(outgoing.message.has_error() ? "closed after error: " + outgoing.message.error().message()
                                                     : std::string("closed by the session"));
    }
  }
}

void TcpServer::rearmTimer() {
  if (finishing_) return;
  std::optional<SteadyClock::time_point> deadline;
  try {
    deadline = handler_.nextDeadline();
  } catch (const std::exception& error) {
    spdlog::error("internal error in nextDeadline: {}", error.what());
  }
  if (deadline == armed_deadline_) return;
  armed_deadline_ = deadline;
  if (!deadline) {
    poll_timer_.cancel();
    return;
  }
  poll_timer_.expires_at(*deadline);  // cancels the previous wait
  poll_timer_.async_wait([this](const asio::error_code& error) {
    if (error || finishing_) return;
    armed_deadline_.reset();
    callHandler(0, "poll", [this] { return handler_.poll(SteadyClock::now()); });
  });
}

void TcpServer::finish(const std::string& why, const std::optional<std::string>& shutdownReason) {
  if (finishing_) return;
  if (shutdownReason) {
    const std::string reason = *shutdownReason;
    callHandler(0, "shutdown", [&] { return handler_.shutdown(reason, SteadyClock::now()); });
  }
  finishing_ = true;
  spdlog::info("{}", why);
  asio::error_code ignored;
  acceptor_.close(ignored);
  poll_timer_.cancel();
  accept_retry_.cancel();
  if (signals_) signals_->cancel(ignored);
  // Copied: each close() erases its entry.
  std::vector<std::shared_ptr<Connection>> open;
  open.reserve(connections_.size());
  for (const auto& entry : connections_) open.push_back(entry.second);
  for (const std::shared_ptr<Connection>& connection : open) connection->close(why);
}

}  // namespace demlink::server
