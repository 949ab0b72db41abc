/// Session recording (contract in session_recorder.hpp). Each event is flushed as it is
/// written, so a server that is killed still leaves every event before it on disk.
#include "demlink/server/cosim/session_recorder.hpp"

#include <stdexcept>
#include <string>

#include "demlink/wire/frame_codec.hpp"

namespace demlink::server {

SessionRecorder::SessionRecorder(const std::filesystem::path& path, const CosimOptions& options)
    : path_(path), start_(std::chrono::steady_clock::now()) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot write the session record " + path.string());
  v1::SessionEvent header;
  header.set_kind(v1::SessionEvent::HEADER);
  *header.mutable_base_scene() = options.base_scene;
  header.set_scene_directory(options.scene_directory.string());
  if (options.data_root) header.set_data_root(options.data_root->string());
  header.set_server_name(options.server_name);
  record(std::move(header));
}

void SessionRecorder::record(v1::SessionEvent event) {
  event.set_elapsed_s(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  const std::string frame = wire::encodeFrame(event);
  out_.write(frame.data(), static_cast<std::streamsize>(frame.size()));
  out_.flush();
  if (!out_) throw std::runtime_error("cannot write the session record " + path_.string());
}

}  // namespace demlink::server
