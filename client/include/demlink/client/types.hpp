#pragma once
/// Plain value types and exceptions of the DEMLink client library.
///
/// Why plain structs: a system-model tool or a small C++ program that drives a component
/// should not need Eigen or the engine's headers; three doubles are all a client ever
/// passes. Why several exception types: a caller reacts differently to "the server said
/// no" (fix the declaration), "the server did not answer in time" (the simulation is
/// stuck) and "the socket is gone" (the server is down).
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "demlink/client/proto_fwd.hpp"

namespace demlink::client {

/// A vector in the world frame (or the frame named by the call) [unit of the call].
struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

/// A rotation w + xi + yj + zk (geometry frame -> world) [-]; default identity.
struct Quat {
  double w = 1.0;
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

/// Count and mass of particles [-], [kg].
struct CountAndMass {
  std::uint64_t count = 0;
  double mass = 0.0;
};

/// The server answered with Error{code, message, component, field}.
class ServerError : public std::runtime_error {
 public:
  explicit ServerError(const v1::Error& error);
  [[nodiscard]] v1::Error_Code code() const { return code_; }
  /// The server's text, without the decoration what() adds.
  [[nodiscard]] const std::string& serverMessage() const { return message_; }
  [[nodiscard]] const std::string& component() const { return component_; }
  [[nodiscard]] const std::string& field() const { return field_; }
  /// The simulation of this connection has ended / the server closes the connection.
  [[nodiscard]] bool fatal() const { return fatal_; }

 private:
  v1::Error_Code code_;
  std::string message_;
  std::string component_;
  std::string field_;
  bool fatal_;
};

/// No answer (or the connection / a send did not complete) within the timeout. The
/// connection is closed afterwards: its position in the message stream is unknown.
class TimeoutError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Connecting failed, the server closed the connection, or it sent bytes that are not a
/// valid ServerMessage.
class ConnectionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The call is not allowed in the session's state (e.g. exchange() before waitCompiled(),
/// a component added after declare()), or the server broke the sequence the protocol
/// promises (an answer for a component that was not waiting for one).
class StateError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// Deletes a schema message the header only declares; defined (and instantiated for the
/// messages the client holds) where the generated code is visible.
template <class Message>
struct ProtoDelete {
  void operator()(Message* message) const;
};
/// Owns a schema message behind a forward declaration (a pimpl per message).
template <class Message>
using ProtoPtr = std::unique_ptr<Message, ProtoDelete<Message>>;

/// Conversions to and from the wire's geometry messages.
[[nodiscard]] v1::Vector3 toProto(const Vec3& v);
[[nodiscard]] v1::Quaternion toProto(const Quat& q);
[[nodiscard]] Vec3 fromProto(const v1::Vector3& v);
/// An unset Quaternion field means identity (geometry.proto).
[[nodiscard]] Quat fromProto(const v1::Quaternion& q, bool present = true);

}  // namespace demlink::client
