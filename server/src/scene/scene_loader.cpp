/// Scene files are parsed with protobuf's own JSON parser (strict: unknown
/// fields are errors) so the file format can never drift from the wire schema.
#include "demlink/server/scene/scene_loader.hpp"

#include <google/protobuf/util/json_util.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/input_file.hpp"

namespace demlink::server {

namespace {

/// Refuses JSON protobuf's parser would misread: a document that is not an object, and
/// nesting deeper than kMaxSceneJsonDepth (a 200,000-deep array came back as an empty
/// scene). Strings are skipped, with their escapes, so brackets inside them do not count.
void checkJsonShape(const std::string& json, const std::string& sourceName, const std::string& kind,
                    const std::string& example) {
  std::size_t k = json.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  while (k < json.size() && std::isspace(static_cast<unsigned char>(json[k])) != 0) ++k;
  if (k == json.size() || json[k] != '{') {
    throw core::InputError(sourceName, "(" + kind + " JSON)",
                           "invalid " + kind + ": a " + kind + " is a JSON object (" + example + ")");
  }
  std::size_t depth = 0;
  std::size_t line = 1;
  bool inString = false;
  for (; k < json.size(); ++k) {
    const char c = json[k];
    if (c == '\n') ++line;
    if (inString) {
      if (c == '\\') {
        ++k;
      } else if (c == '"') {
        inString = false;
      }
    } else if (c == '"') {
      inString = true;
    } else if (c == '{' || c == '[') {
      if (++depth > kMaxSceneJsonDepth) {
        throw core::InputError(sourceName + ":line " + std::to_string(line), "(" + kind + " JSON)",
                               "invalid " + kind + ": nested deeper than " + std::to_string(kMaxSceneJsonDepth) + " levels");
      }
    } else if ((c == '}' || c == ']') && depth > 0) {
      --depth;
    }
  }
}

}  // namespace

void parseJsonMessage(const std::string& json, const std::string& sourceName, const std::string& kind,
                      const std::string& example, google::protobuf::Message& message) {
  checkJsonShape(json, sourceName, kind, example);
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = false;
  const auto status = google::protobuf::util::JsonStringToMessage(json, &message, options);
  if (!status.ok()) {
    throw core::InputError(sourceName, "(" + kind + " JSON)", "invalid " + kind + ": " + std::string(status.message()));
  }
}

v1::Scene parseSceneJson(const std::string& json, const std::string& sourceName) {
  v1::Scene scene;
  parseJsonMessage(json, sourceName, "scene", "{\"components\": [...]}", scene);
  return scene;
}

v1::Scene loadSceneFile(const std::string& path) {
  return parseSceneJson(core::readInputFile("scene file", path), path);
}

std::string sceneToJson(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.add_whitespace = true;
  options.preserve_proto_field_names = true;
  std::string json;
  const auto status = google::protobuf::util::MessageToJsonString(message, &json, options);
  if (!status.ok()) throw std::runtime_error("cannot print scene as JSON: " + std::string(status.message()));
  return json;
}

}  // namespace demlink::server
