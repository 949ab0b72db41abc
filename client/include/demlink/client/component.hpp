#pragma once
/// The part every client-side component shares: its declaration (the very message a scene
/// file lists), the ids and interval the server compiled for it, where it stands in the
/// exchange (next due step, waiting for an answer), and its latest outputs.
///
/// Why the full ComponentDeclaration is exposed: the typed setters cover the fields a
/// system model usually sets; everything else (size distributions, clump templates, frame
/// motion...) is reachable through declaration() / message() without the client library
/// having to mirror every schema field.
#include <cstdint>
#include <string>

#include "demlink/client/types.hpp"

namespace demlink::client {

class Session;

class Component {
 public:
  virtual ~Component() = default;
  Component(const Component&) = delete;
  Component& operator=(const Component&) = delete;

  [[nodiscard]] const std::string& name() const;
  /// The ComponentDeclaration field name of the kind, e.g. "rigid_body".
  [[nodiscard]] std::string kind() const;

  /// Time between this component's packages [s]; 0: declared only, never exchanged.
  void setCommunicationInterval(double seconds);
  [[nodiscard]] double communicationInterval() const;

  /// The declaration as it will be (or was) sent. Changing it after declare() has no effect.
  [[nodiscard]] v1::ComponentDeclaration& declaration() { return *declaration_; }
  [[nodiscard]] const v1::ComponentDeclaration& declaration() const { return *declaration_; }

  // --- After Session::waitCompiled() --------------------------------------------------
  [[nodiscard]] bool compiled() const { return compiled_; }
  /// The component_id of its DataPackages [-].
  [[nodiscard]] std::uint32_t id() const { return id_; }
  /// Communication interval in steps [-]; 0: never exchanged.
  [[nodiscard]] std::uint64_t intervalSteps() const { return interval_steps_; }
  [[nodiscard]] bool exchanged() const { return compiled_ && interval_steps_ > 0; }
  /// The step its next package is for (a multiple of intervalSteps()) [-].
  [[nodiscard]] std::uint64_t nextSendStep() const { return next_send_step_; }
  /// Its package was sent and the answer (at nextSendStep() + intervalSteps()) has not arrived.
  [[nodiscard]] bool awaitingAnswer() const { return awaiting_; }
  /// Latest outputs: Compiled's initial outputs, then the answer of each interval.
  [[nodiscard]] const v1::DataPackage& outputs() const { return *outputs_; }
  /// The step the latest outputs are for [-].
  [[nodiscard]] std::uint64_t outputStep() const;

 protected:
  explicit Component(std::string name);
  /// Writes this component's inputs into a package (default: none; a sensor's empty
  /// package still tells the server "go on").
  virtual void writeInputs(v1::DataPackage& package) const;
  /// Called once the package went out (one-shot inputs are cleared here).
  virtual void inputsSent() {}
  /// Last chance to complete the declaration before it is sent.
  virtual void prepareDeclaration() {}

 private:
  friend class Session;
  ProtoPtr<v1::ComponentDeclaration> declaration_;
  bool declared_ = false;
  bool compiled_ = false;
  std::uint32_t id_ = 0;
  std::uint64_t interval_steps_ = 0;
  std::uint64_t next_send_step_ = 0;
  bool awaiting_ = false;
  ProtoPtr<v1::DataPackage> outputs_;
};

}  // namespace demlink::client
