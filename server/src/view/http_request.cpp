/// Incremental HTTP/1.1 request parsing (contract in http_request.hpp).
#include "demlink/server/view/http_request.hpp"

#include <algorithm>
#include <cctype>

namespace demlink::server {
namespace {

std::string toLower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

std::string_view trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

/// RFC 9110 token characters (field names, methods).
bool isTokenChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || std::string_view("!#$%&'*+-.^_`|~").find(c) !=
                                                                   std::string_view::npos;
}

int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::optional<std::string> percentDecode(std::string_view text, bool plusIsSpace) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (c == '%') {
      if (i + 2 >= text.size()) return std::nullopt;
      const int high = hexValue(text[i + 1]);
      const int low = hexValue(text[i + 2]);
      if (high < 0 || low < 0) return std::nullopt;
      c = static_cast<char>(high * 16 + low);
      i += 2;
    } else if (c == '+' && plusIsSpace) {
      c = ' ';
    }
    if (c == '\0') return std::nullopt;
    out += c;
  }
  return out;
}

std::optional<std::string_view> HttpRequest::header(const std::string& name) const {
  const auto found = headers.find(name);
  if (found == headers.end()) return std::nullopt;
  return std::string_view(found->second);
}

bool HttpRequest::headerListsToken(const std::string& name, std::string_view token) const {
  const std::optional<std::string_view> value = header(name);
  if (!value) return false;
  const std::string wanted = toLower(token);
  std::string_view rest = *value;
  while (!rest.empty()) {
    const std::size_t comma = rest.find(',');
    const std::string_view item = trim(rest.substr(0, comma));
    if (toLower(item) == wanted) return true;
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return false;
}

HttpRequestParser::State HttpRequestParser::fail(int status, std::string reason) {
  state_ = State::kError;
  error_status_ = status;
  error_reason_ = std::move(reason);
  return state_;
}

HttpRequestParser::State HttpRequestParser::feed(std::string_view bytes) {
  if (state_ != State::kIncomplete) return state_;
  buffer_.append(bytes);
  const std::size_t end = buffer_.find("\r\n\r\n");
  if (end == std::string::npos) {
    if (buffer_.size() > kMaxHttpHeaderBytes) return fail(431, "request header block over 8192 bytes");
    return state_;
  }
  if (end + 4 > kMaxHttpHeaderBytes) return fail(431, "request header block over 8192 bytes");
  leftover_ = buffer_.substr(end + 4);
  const std::string block = buffer_.substr(0, end + 2);  // every line ends with CRLF
  buffer_.clear();
  buffer_.shrink_to_fit();
  return parseHeaderBlock(block);
}

HttpRequestParser::State HttpRequestParser::parseHeaderBlock(std::string_view block) {
  const std::size_t lineEnd = block.find("\r\n");
  const std::string_view line = block.substr(0, lineEnd);
  // request-line = method SP request-target SP HTTP-version
  const std::size_t firstSpace = line.find(' ');
  const std::size_t lastSpace = line.rfind(' ');
  if (firstSpace == std::string_view::npos || lastSpace == firstSpace) {
    return fail(400, "malformed request line");
  }
  const std::string_view method = line.substr(0, firstSpace);
  const std::string_view target = line.substr(firstSpace + 1, lastSpace - firstSpace - 1);
  const std::string_view version = line.substr(lastSpace + 1);
  if (method.empty() || !std::all_of(method.begin(), method.end(), isTokenChar)) {
    return fail(400, "malformed method");
  }
  if (version != "HTTP/1.1" && version != "HTTP/1.0") return fail(505, "only HTTP/1.0 and HTTP/1.1 are served");
  if (target.empty() || target.front() != '/') return fail(400, "request target must be an absolute path");
  if (target.size() > 2048) return fail(414, "request target over 2048 bytes");
  if (method != "GET" && method != "HEAD") return fail(405, "only GET and HEAD are served");
  request_.method = std::string(method);
  request_.target = std::string(target);

  const std::size_t question = target.find('?');
  const std::optional<std::string> path = percentDecode(target.substr(0, question), false);
  if (!path) return fail(400, "malformed percent escape in the path");
  request_.path = *path;
  if (question != std::string_view::npos) {
    std::string_view query = target.substr(question + 1);
    while (!query.empty()) {
      const std::size_t amp = query.find('&');
      const std::string_view pair = query.substr(0, amp);
      const std::size_t equals = pair.find('=');
      const std::optional<std::string> name = percentDecode(pair.substr(0, equals), true);
      const std::optional<std::string> value =
          percentDecode(equals == std::string_view::npos ? std::string_view() : pair.substr(equals + 1), true);
      if (!name || !value) return fail(400, "malformed percent escape in the query");
      if (!name->empty()) request_.query[*name] = *value;
      if (amp == std::string_view::npos) break;
      query.remove_prefix(amp + 1);
    }
  }

  std::size_t fields = 0;
  std::size_t position = lineEnd + 2;
  while (position < block.size()) {
    const std::size_t next = block.find("\r\n", position);
    const std::string_view field = block.substr(position, next - position);
    position = next + 2;
    if (++fields > kMaxHttpHeaderFields) return fail(431, "more than 64 header fields");
    const std::size_t colon = field.find(':');
    if (colon == std::string_view::npos || colon == 0) return fail(400, "header field without a name");
    const std::string_view name = field.substr(0, colon);
    if (!std::all_of(name.begin(), name.end(), isTokenChar)) return fail(400, "malformed header field name");
    const std::string_view value = trim(field.substr(colon + 1));
    if (std::any_of(value.begin(), value.end(), [](char c) { return c == '\r' || c == '\n' || c == '\0'; })) {
      return fail(400, "control character in a header field value");
    }
    std::string& stored = request_.headers[toLower(name)];
    stored += stored.empty() ? std::string(value) : ", " + std::string(value);
  }
  if (request_.headers.contains("content-length") || request_.headers.contains("transfer-encoding")) {
    const std::optional<std::string_view> length = request_.header("content-length");
    if (!length || *length != "0") return fail(400, "the view takes no request body");
  }
  state_ = State::kComplete;
  return state_;
}

}  // namespace demlink::server
