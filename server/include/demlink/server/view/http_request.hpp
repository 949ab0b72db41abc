#pragma once
/// The part of HTTP/1.1 (RFC 9112) the view's page server needs: a GET request's line and
/// header fields, read incrementally from a socket, with hard limits so that no client can
/// make the server buffer more than kMaxHttpHeaderBytes or wait on a malformed request.
/// A request with a body is refused (the view never takes one).
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace demlink::server {

/// Most bytes of a request line and its header fields together [B].
inline constexpr std::size_t kMaxHttpHeaderBytes = 8192;
/// Most header fields in one request [-].
inline constexpr std::size_t kMaxHttpHeaderFields = 64;

struct HttpRequest {
  std::string method;  ///< "GET", "HEAD"
  std::string target;  ///< as sent: path and query
  std::string path;    ///< percent-decoded path, always starting with '/'
  std::map<std::string, std::string> query;    ///< percent-decoded name -> value
  std::map<std::string, std::string> headers;  ///< lower-case field name -> value (repeats joined by ", ")

  /// The header field's value, if present (`name` in lower case).
  [[nodiscard]] std::optional<std::string_view> header(const std::string& name) const;
  /// Whether the comma-separated header `name` lists `token` (case-insensitive), as
  /// "Connection: keep-alive, Upgrade" lists "upgrade".
  [[nodiscard]] bool headerListsToken(const std::string& name, std::string_view token) const;
};

/// Reads one request from the bytes a connection delivers.
class HttpRequestParser {
 public:
  enum class State { kIncomplete, kComplete, kError };

  /// Appends `bytes` and parses once the header block is complete. Bytes after the
  /// request's blank line are kept in leftover(). After kComplete or kError further
  /// calls return the same state.
  State feed(std::string_view bytes);

  [[nodiscard]] State state() const { return state_; }
  [[nodiscard]] const HttpRequest& request() const { return request_; }
  /// On kError: the HTTP status to answer (400, 405, 414, 431, 501 or 505) and why.
  [[nodiscard]] int errorStatus() const { return error_status_; }
  [[nodiscard]] const std::string& errorReason() const { return error_reason_; }
  /// Bytes received after the end of the request's header block.
  [[nodiscard]] std::string_view leftover() const { return leftover_; }

 private:
  State fail(int status, std::string reason);
  State parseHeaderBlock(std::string_view block);

  std::string buffer_;
  std::string leftover_;
  HttpRequest request_;
  State state_ = State::kIncomplete;
  int error_status_ = 0;
  std::string error_reason_;
};

/// Decodes %XX escapes (and '+' as a space when `plusIsSpace`, as in a query); nullopt
/// for a malformed escape or a decoded NUL.
[[nodiscard]] std::optional<std::string> percentDecode(std::string_view text, bool plusIsSpace);

}  // namespace demlink::server
