#pragma once
/// Components that set up the simulation: SimulationBox (the one mandatory scene-wide
/// component; it may also be exchanged to read the world's totals and to change gravity
/// or the frame's motion at run time), Material, Plane, SingleParticle, ParticleSystem.
/// Units are SI throughout; each setter names its unit.
#include <cstdint>
#include <string>

#include "demlink/client/component.hpp"

namespace demlink::client {

class SimulationBox : public Component {
 public:
  explicit SimulationBox(std::string name = "simulation_box");
  SimulationBox& setTimeStep(double seconds);         ///< [s]
  SimulationBox& setEndTime(double seconds);          ///< [s]; required by the compiler
  SimulationBox& setInitialGravity(const Vec3& g);    ///< declared gravity [m/s^2]
  SimulationBox& setBounds(const Vec3& lower, const Vec3& upper);  ///< fixed domain [m]
  /// Largest restitution error the server's time-step limit allows [-], in (0, 1); unset:
  /// 0.01. A larger value accepts a larger time step: it trades accuracy for speed.
  SimulationBox& setRestitutionTolerance(double tolerance);
  /// Compile once this many components are declared (this box included) [-].
  SimulationBox& setExpectedCount(std::uint32_t count);
  SimulationBox& addExpectedName(const std::string& name);
  SimulationBox& setClientTimeout(double seconds);    ///< [s]
  SimulationBox& setOutputDirectory(const std::string& directory);
  [[nodiscard]] v1::SimulationBox& message();

  // Inputs: one-shot, sent with the box's next package only ("omitted: unchanged").
  void setGravity(const Vec3& g);  ///< [m/s^2]
  /// Frame motion (docs/frame_and_facets.md): [m/s^2], [rad/s], [rad/s^2], [m].
  void setFrame(const Vec3& linearAcceleration, const Vec3& angularVelocity, const Vec3& angularAcceleration,
                const Vec3& origin = {});

  // Outputs of the latest interval.
  [[nodiscard]] double time() const;               ///< [s]
  [[nodiscard]] std::uint64_t particleCount() const;  ///< [-]
  [[nodiscard]] double totalMass() const;          ///< [kg]
  [[nodiscard]] double kineticEnergy() const;      ///< [J]
  [[nodiscard]] double stepRate() const;           ///< engine steps per wall-clock second [1/s]

 protected:
  void writeInputs(v1::DataPackage& package) const override;
  void inputsSent() override;

 private:
  ProtoPtr<v1::SimulationBoxInput> pending_;
};

class Material : public Component {
 public:
  /// The material's name is the component's name (planes and bodies refer to it).
  explicit Material(std::string name);
  Material& setDatabaseName(const std::string& name);  ///< e.g. "gravel" (data/materials.csv)
  Material& setDensity(double kgPerM3);                ///< [kg/m^3]
  Material& setYoungsModulus(double pascal);           ///< [Pa]
  Material& setPoissonRatio(double ratio);             ///< [-]
  Material& setRestitution(double coefficient);        ///< [-]
  Material& setSlidingFriction(double coefficient);    ///< [-]
  Material& setRollingFriction(double coefficient);    ///< [-]
  [[nodiscard]] v1::Material& message();
};

class Plane : public Component {
 public:
  explicit Plane(std::string name);
  Plane& setPoint(const Vec3& point);    ///< [m]
  Plane& setNormal(const Vec3& normal);  ///< towards the particles [-]
  Plane& setMaterial(const std::string& material);
  [[nodiscard]] v1::Plane& message();
};

class SingleParticle : public Component {
 public:
  explicit SingleParticle(std::string name);
  SingleParticle& setMaterial(const std::string& material);
  SingleParticle& setPosition(const Vec3& centre);         ///< [m]
  SingleParticle& setVelocity(const Vec3& velocity);       ///< [m/s]
  SingleParticle& setAngularVelocity(const Vec3& omega);   ///< [rad/s]
  SingleParticle& setDiameter(double metres);              ///< [m]
  [[nodiscard]] v1::SingleParticle& message();
};

/// Particles loaded from a file on the SERVER (CSV or checkpoint).
class ParticleSystem : public Component {
 public:
  explicit ParticleSystem(std::string name);
  ParticleSystem& setCsvFile(const std::string& path);
  ParticleSystem& setCheckpointFile(const std::string& path);
  [[nodiscard]] v1::ParticleSystem& message();
};

}  // namespace demlink::client
