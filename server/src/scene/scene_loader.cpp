/// Scene files are parsed with protobuf's own JSON parser (strict: unknown
/// fields are errors) so the file format can never drift from the wire schema.
#include "demlink/server/scene/scene_loader.hpp"

#include <google/protobuf/util/json_util.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "demlink/core/input_error.hpp"

namespace demlink::server {

v1::Scene parseSceneJson(const std::string& json, const std::string& sourceName) {
  v1::Scene scene;
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = false;
  const auto status = google::protobuf::util::JsonStringToMessage(json, &scene, options);
  if (!status.ok()) {
    throw core::InputError(sourceName, "(scene JSON)", "invalid scene: " + std::string(status.message()));
  }
  return scene;
}

v1::Scene loadSceneFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw core::InputError(path, "(scene file)", "file not found");
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw core::InputError(path, "(scene file)", "not a regular file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::InputError(path, "(scene file)", std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw core::InputError(path, "(scene file)", "read error");
  return parseSceneJson(text.str(), path);
}

std::string sceneToJson(const v1::Scene& scene) {
  google::protobuf::util::JsonPrintOptions options;
  options.add_whitespace = true;
  options.preserve_proto_field_names = true;
  std::string json;
  const auto status = google::protobuf::util::MessageToJsonString(scene, &json, options);
  if (!status.ok()) throw std::runtime_error("cannot print scene as JSON: " + std::string(status.message()));
  return json;
}

}  // namespace demlink::server
