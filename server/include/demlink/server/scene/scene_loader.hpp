#pragma once
/// Reading and writing scene files.
///
/// A scene file is the canonical protobuf JSON form of demlink.v1.Scene (see
/// proto/demlink/v1/scene.proto): the same component declarations a client sends
/// over TCP. Parsing is strict: an unknown field is an error (it is almost always
/// a typo that would otherwise silently take a default). Field names may be the
/// proto names (snake_case) or their lowerCamelCase JSON names.
#include <cstddef>
#include <string>

#include "demlink/v1/scene.pb.h"

namespace demlink::server {

/// Parses a scene file. Throws core::InputError with field = `path` for a missing
/// or unreadable file and for invalid JSON or schema errors (the reason carries
/// the parser's message, which names the offending field, e.g.
/// "(components[0].simulation_box) time_stepp: Cannot find field.").
[[nodiscard]] v1::Scene loadSceneFile(const std::string& path);

/// Deepest nesting of objects and arrays a scene file may have [-] (the deepest schema
/// path is about 8; protobuf's parser misreads very deep documents).
inline constexpr std::size_t kMaxSceneJsonDepth = 64;

/// Parses scene JSON held in memory; `sourceName` takes the place of the path in errors.
/// A document that is not a JSON object or nests deeper than kMaxSceneJsonDepth is an
/// InputError naming the source (and the line where the nesting got too deep).
[[nodiscard]] v1::Scene parseSceneJson(const std::string& json, const std::string& sourceName);

/// Parses a JSON document of another file format the project defines in protobuf (e.g.
/// demlink-calibrate's targets) into `message` with the scene files' rules: a JSON object,
/// nested at most kMaxSceneJsonDepth deep, strict about unknown fields. Errors are
/// InputError naming `sourceName`; `kind` ("scene") and `example` ("{...}") word them.
void parseJsonMessage(const std::string& json, const std::string& sourceName, const std::string& kind,
                      const std::string& example, google::protobuf::Message& message);

/// A scene, or one of its parts (e.g. a ComponentDeclaration), as indented JSON with proto
/// field names: what a scene file looks like.
[[nodiscard]] std::string sceneToJson(const google::protobuf::Message& message);

}  // namespace demlink::server
