/// Page requests (contract in view_requests.hpp).
#include "view_requests.hpp"

#include <charconv>
#include <cmath>

namespace demlink::server {
namespace {

std::string describe(std::string_view name, std::string_view value, std::string_view reason) {
  std::string shown(value.substr(0, 40));
  for (char& c : shown) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  }
  return std::string(name) + " = \"" + shown + "\": " + std::string(reason);
}

template <class T>
std::optional<T> parseNumber(std::string_view text) {
  T value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace

std::string_view colourFieldName(ColourField field) {
  switch (field) {
    case ColourField::kSpeed:
      return "speed";
    case ColourField::kForce:
      return "force";
    case ColourField::kMaterial:
      return "material";
    case ColourField::kId:
      return "id";
  }
  return "speed";
}

std::optional<ViewRequest> parseViewRequest(std::string_view text, double maxRate, std::string& error) {
  ViewRequest request;
  while (!text.empty()) {
    const std::size_t start = text.find_first_not_of(" ;\t\r\n");
    if (start == std::string_view::npos) break;
    text.remove_prefix(start);
    const std::size_t end = text.find_first_of(" ;\t\r\n");
    const std::string_view item = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end);
    const std::size_t equals = item.find('=');
    if (equals == std::string_view::npos) {
      error = describe("request", item, "expected name=value");
      return std::nullopt;
    }
    const std::string_view name = item.substr(0, equals);
    const std::string_view value = item.substr(equals + 1);
    if (name == "rate") {
      const std::optional<double> rate = parseNumber<double>(value);
      if (!rate || !std::isfinite(*rate) || *rate <= 0.0 || *rate > maxRate) {
        error = describe(name, value, "frames per second must be > 0 and <= " + std::to_string(maxRate));
        return std::nullopt;
      }
      request.rate = *rate;
    } else if (name == "max") {
      const std::optional<std::size_t> count = parseNumber<std::size_t>(value);
      if (!count || *count > kMaxViewParticles) {
        error = describe(name, value, "particles per frame must be an integer in [0, 10000000]");
        return std::nullopt;
      }
      request.max_particles = *count;
    } else if (name == "colour" || name == "color") {
      if (value == "speed") {
        request.colour = ColourField::kSpeed;
      } else if (value == "force") {
        request.colour = ColourField::kForce;
      } else if (value == "material") {
        request.colour = ColourField::kMaterial;
      } else if (value == "id") {
        request.colour = ColourField::kId;
      } else {
        error = describe(name, value, "one of speed, force, material, id");
        return std::nullopt;
      }
    } else if (name == "frame") {
      const std::optional<std::uint32_t> frame = parseNumber<std::uint32_t>(value);
      if (!frame) {
        error = describe(name, value, "a frame index, an integer >= 0");
        return std::nullopt;
      }
      request.frame = *frame;
    } else if (name == "sim") {
      const std::optional<std::uint64_t> id = parseNumber<std::uint64_t>(value);
      if (!id || *id == 0) {
        error = describe(name, value, "a simulation id, an integer >= 1");
        return std::nullopt;
      }
      request.simulation = *id;
    } else {
      error = describe(name, value, "unknown request (rate, max, colour, frame, sim)");
      return std::nullopt;
    }
  }
  return request;
}

}  // namespace demlink::server
