#pragma once
/// The components of one connection and their exchange with the server.
///
/// Sequence: add components, declare(), waitCompiled(), then exchange() in a loop, then
/// finish(). Blocking semantics of exchange() (the server answers a component at the END
/// of its interval):
///   - It sends the package of every component of this session that is due at
///     currentStep() (step % intervalSteps == 0, and its previous answer has arrived),
///   - then blocks until the server has simulated up to the NEXT step at which any
///     component of this session is due, and has answered every component whose interval
///     ends there,
///   - and moves currentStep() to that step. Outputs are then readable on the components.
/// With intervals 2 and 3 steps, exchange() returns at steps 2, 3, 4, 6, 8, 9, ...; the
/// 3-step component's answer is only there when currentStep() is a multiple of 3, before
/// that its outputs are those of its previous interval.
///
/// Why one session must not wait for another in the same thread: the server advances only
/// when EVERY due component of EVERY connection has sent its package. Two sessions driven
/// one after the other from one thread with exchange() deadlock (the first waits for an
/// answer that needs the second's package). Such a caller uses the split form instead:
/// send() all due components of all sessions first, then receive() their answers — the C
/// ABI's per-component exchange calls do exactly that (receive the answer of the interval
/// that ended, then send the next package).
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "demlink/client/component.hpp"
#include "demlink/client/connection.hpp"

namespace demlink::client {

class Session {
 public:
  /// The connection must outlive the session and be connected (connect() done).
  explicit Session(Connection& connection);

  /// Creates a component owned by the session; the reference stays valid for its lifetime.
  template <class T, class... Args>
  T& add(Args&&... args) {
    requireNotCompiled("add");
    auto component = std::make_unique<T>(std::forward<Args>(args)...);
    T& ref = *component;
    components_.push_back(std::move(component));
    return ref;
  }
  /// Takes ownership of a component built elsewhere (e.g. by kind name in the C ABI).
  Component& adopt(std::unique_ptr<Component> component) {
    requireNotCompiled("adopt");
    components_.push_back(std::move(component));
    return *components_.back();
  }
  [[nodiscard]] std::size_t size() const { return components_.size(); }
  [[nodiscard]] Component& component(std::size_t index) { return *components_.at(index); }
  /// nullptr when no component has that name.
  [[nodiscard]] Component* find(const std::string& name);

  /// Sends a Declare for every component not declared yet (order of add()).
  void declare();
  /// Takes `component` and declares it, unless this session already has one of that name:
  /// then an identical declaration (a tool repeating its initialisation) returns the one
  /// already declared and sends nothing, a different one throws StateError. `index`
  /// receives the component's position (the C ABI's handle).
  Component& declareOnce(std::unique_ptr<Component> component, std::size_t& index);
  /// Declares what is pending, then tells the server this connection declares nothing more
  /// (DeclarationsDone): once every connection has, the server compiles without an expected
  /// count or a quiet period. Idempotent; after the compile it sends nothing.
  void declarationsDone();
  [[nodiscard]] bool declarationsDoneSent() const { return done_sent_; }
  /// Blocks until Compiled: assigns ids and intervals, stores the report and the initial
  /// outputs (a component's outputs() at step 0). Throws ServerError when the compiler
  /// refused the scene.
  const v1::Compiled& waitCompiled();
  [[nodiscard]] bool isCompiled() const { return compiled_flag_; }
  [[nodiscard]] const v1::Compiled& compiled() const { return *compiled_; }
  [[nodiscard]] double timeStep() const;         ///< [s]
  [[nodiscard]] std::uint64_t endStep() const;  ///< 0: open-ended
  [[nodiscard]] const v1::CompileReport& report() const;
  /// The compile report as text (what the server logs: time step, components, warnings).
  [[nodiscard]] std::string reportText() const;

  /// The step the session stands at: the step of the latest answers [-]; after
  /// waitCompiled(), Compiled.start_step (0, or the step of a checkpoint the server restored).
  [[nodiscard]] std::uint64_t currentStep() const { return current_; }
  [[nodiscard]] double time() const { return static_cast<double>(current_) * timeStep(); }  ///< [s]
  /// Components whose package is due at currentStep().
  [[nodiscard]] std::vector<Component*> due() const;

  /// One exchange (see the file comment). Returns false once the simulation has finished
  /// (the end step was reached or the server ended it); finishedInfo() says why.
  bool exchange();

  // --- Split form, per component ---------------------------------------------------
  /// Sends `component`'s package for its due step (nextSendStep()).
  void send(Component& component);
  /// Reads messages until `component`'s answer has arrived (answers of other components
  /// of this session are stored as they come). False: the simulation finished first.
  bool receive(Component& component);
  /// Reads the next answer of any component; nullptr: the simulation finished.
  Component* receiveAny();

  /// Sends Bye and blocks until Finished (answers still in flight are stored). When the
  /// simulation has already finished, returns its Finished without sending anything.
  const v1::Finished& finish(const std::string& reason = "client finished");
  /// Sends Bye without waiting (for callers that must not block, e.g. Modelica terminal()).
  void sendBye(const std::string& reason = "client finished");
  /// Blocks until Finished.
  const v1::Finished& waitFinished();
  [[nodiscard]] bool finished() const { return finished_flag_; }
  [[nodiscard]] const v1::Finished& finishedInfo() const { return *finished_; }
  /// Why the simulation finished (finishedInfo().reason()); empty while it runs.
  [[nodiscard]] std::string finishedReason() const;

 private:
  void requireNotCompiled(const char* what) const;
  void requireCompiled(const char* what) const;
  /// Reads one message and applies it; returns the component an answer was for.
  Component* pump();
  void applyCompiled(const v1::Compiled& compiled);
  Component* applyData(const v1::DataPackage& package);

  Connection& connection_;
  std::vector<std::unique_ptr<Component>> components_;
  bool compiled_flag_ = false;
  ProtoPtr<v1::Compiled> compiled_;
  std::uint64_t current_ = 0;
  bool bye_sent_ = false;
  bool done_sent_ = false;
  bool finished_flag_ = false;
  ProtoPtr<v1::Finished> finished_;
};

}  // namespace demlink::client
