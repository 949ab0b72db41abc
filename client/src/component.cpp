/// Component basics: the kind name comes from the declaration's `kind` oneof through
/// protobuf reflection, so a new schema kind needs no change here.
#include "demlink/client/component.hpp"

#include <utility>

namespace demlink::client {

Component::Component(std::string name) { declaration_.set_name(std::move(name)); }

std::string Component::kind() const {
  const auto* oneof = v1::ComponentDeclaration::descriptor()->FindOneofByName("kind");
  const auto* field = declaration_.GetReflection()->GetOneofFieldDescriptor(declaration_, oneof);
  return field == nullptr ? std::string() : std::string(field->name());
}

void Component::writeInputs(v1::DataPackage& /*package*/) const {}

}  // namespace demlink::client
