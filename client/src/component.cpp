/// Component basics: the kind name comes from the declaration's `kind` oneof through
/// protobuf reflection, so a new schema kind needs no change here.
#include "demlink/client/component.hpp"

#include <utility>

#include "demlink/v1/protocol.pb.h"

namespace demlink::client {

template <class Message>
void ProtoDelete<Message>::operator()(Message* message) const {
  delete message;
}
// Every message a public header holds through ProtoPtr.
template struct ProtoDelete<v1::ComponentDeclaration>;
template struct ProtoDelete<v1::DataPackage>;
template struct ProtoDelete<v1::Compiled>;
template struct ProtoDelete<v1::Finished>;
template struct ProtoDelete<v1::Welcome>;
template struct ProtoDelete<v1::RigidBodyInput>;
template struct ProtoDelete<v1::DeformableBodyInput>;
template struct ProtoDelete<v1::SimulationBoxInput>;
template struct ProtoDelete<v1::RegionInput>;
template struct ProtoDelete<v1::ParticleSourceInput>;
template struct ProtoDelete<v1::ParticleSinkInput>;

Component::Component(std::string name)
    : declaration_(new v1::ComponentDeclaration()), outputs_(new v1::DataPackage()) {
  declaration_->set_name(std::move(name));
}

const std::string& Component::name() const { return declaration_->name(); }
void Component::setCommunicationInterval(double seconds) { declaration_->set_communication_interval(seconds); }
double Component::communicationInterval() const { return declaration_->communication_interval(); }
std::uint64_t Component::outputStep() const { return outputs_->step(); }

std::string Component::kind() const {
  const auto* oneof = v1::ComponentDeclaration::descriptor()->FindOneofByName("kind");
  const auto* field = declaration_->GetReflection()->GetOneofFieldDescriptor(*declaration_, oneof);
  return field == nullptr ? std::string() : std::string(field->name());
}

void Component::writeInputs(v1::DataPackage& /*package*/) const {}

}  // namespace demlink::client
