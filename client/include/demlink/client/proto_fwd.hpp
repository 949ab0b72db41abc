#pragma once
/// Forward declarations of the schema's messages (proto/demlink/v1) the client's public
/// headers name.
///
/// Why not the generated headers: an installed C++ client must compile against its own
/// headers alone, without protoc's output or a matching protobuf version. A caller that
/// edits a declaration() or reads outputs() beyond the typed accessors includes the
/// generated headers itself ("demlink/v1/scene.pb.h", "demlink/v1/protocol.pb.h").
namespace demlink::v1 {

class ClientMessage;
class ClumpTemplate;
class CompileReport;
class Compiled;
class ComponentDeclaration;
class DataPackage;
class DeformableBodyInput;
class Error;
class FemBody;
class Finished;
class FlowSensor;
class MassSpringBody;
class Material;
class NodeSet;
class ParallelBonds;
class ParticleSink;
class ParticleSinkInput;
class ParticleSource;
class ParticleSourceInput;
class ParticleSystem;
class ParticleView;
class ParticleViewOutput;
class PitGenerator;
class Plane;
class Quaternion;
class RegionInput;
class RegionSensor;
class RigidBody;
class RigidBodyInput;
class ServerMessage;
class SimulationBox;
class SimulationBoxInput;
class SingleParticle;
class Vector3;
class Welcome;

// The generated enums have the fixed underlying type int, so they can be declared opaquely
// (v1::Error::Code and v1::RigidBody::Motion are aliases of these).
enum Error_Code : int;
enum RigidBody_Motion : int;

}  // namespace demlink::v1
