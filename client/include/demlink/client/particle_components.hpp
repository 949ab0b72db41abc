#pragma once
/// Components that insert or remove particles: ParticleSource (steady stream into a box
/// or disc), ParticleSink (removes what enters a volume), PitGenerator (a settled bed at
/// step 0), and ClumpTemplate (a multisphere shape sources and pit generators insert
/// instead of spheres). Sources and sinks report counts and masses per interval and in total.
#include <cstdint>
#include <string>
#include <vector>

#include "demlink/client/component.hpp"

namespace demlink::client {

/// A rigid multisphere shape (docs/clumps.md): member spheres with their offsets in the
/// template's own frame. It has no material: a source or pit generator that names it
/// inserts clumps of it in its own material. demlink-clump-fit writes one fitted to an STL.
class ClumpTemplate : public Component {
 public:
  explicit ClumpTemplate(std::string name);
  /// One member sphere: centre in the template's frame [m], radius [m].
  ClumpTemplate& addSphere(const Vec3& offset, double radius);
  [[nodiscard]] v1::ClumpTemplate& message();
};

class ParticleSource : public Component {
 public:
  explicit ParticleSource(std::string name);
  ParticleSource& setMaterial(const std::string& material);
  ParticleSource& setRadius(double metres);                    ///< one radius [m]
  ParticleSource& setRadiusRange(double rMin, double rMax);    ///< uniform in [rMin, rMax] [m]
  /// pdf linear from weightAtMin at rMin to weightAtMax at rMax [m], [-].
  ParticleSource& setLinearSizes(double rMin, double rMax, double weightAtMin, double weightAtMax);
  /// Normal(mean, std) truncated to [rMin, rMax] [m].
  ParticleSource& setNormalSizes(double mean, double std, double rMin, double rMax);
  /// One of `radii` [m] with probability proportional to `weights` [-] (empty: equal).
  ParticleSource& setDiscreteSizes(const std::vector<double>& radii, const std::vector<double>& weights = {});
  ParticleSource& setBox(const Vec3& centre, const Vec3& halfExtents, const Quat& orientation = {});  ///< [m]
  ParticleSource& setDisc(const Vec3& centre, const Vec3& normal, double radius, double thickness = 0.0);  ///< [m]
  ParticleSource& setRateParticles(double perSecond);          ///< [1/s]
  ParticleSource& setRateMass(double kgPerSecond);             ///< [kg/s]
  ParticleSource& setStartTime(double seconds);                ///< [s]
  ParticleSource& setStopTime(double seconds);                 ///< [s]
  ParticleSource& setVelocity(const Vec3& velocity);           ///< initial velocity [m/s]
  ParticleSource& setSeed(std::uint64_t seed);
  ParticleSource& attachTo(const std::string& meshComponent);  ///< region in that body's frame
  /// Insert clumps of the named ClumpTemplate instead of spheres (then set no sizes; the
  /// rate counts clumps).
  ParticleSource& setClumpTemplate(const std::string& templateName);
  [[nodiscard]] v1::ParticleSource& message();

  // Run-time inputs: one-shot, sent with the next package (omitted: unchanged).
  void setEnabled(bool on);      ///< an off source inserts nothing
  void changeRate(double rate);  ///< in the declared unit: [1/s] or [kg/s], >= 0

  [[nodiscard]] CountAndMass insertedInterval() const;  ///< during the latest interval
  [[nodiscard]] CountAndMass insertedTotal() const;     ///< since step 0
  [[nodiscard]] CountAndMass shortfallTotal() const;    ///< requested but not placed, since step 0

 protected:
  void writeInputs(v1::DataPackage& package) const override;
  void inputsSent() override;

 private:
  ProtoPtr<v1::ParticleSourceInput> pending_;
};

class ParticleSink : public Component {
 public:
  explicit ParticleSink(std::string name);
  ParticleSink& setBox(const Vec3& centre, const Vec3& size, const Quat& orientation = {});  ///< [m]
  ParticleSink& setSphere(const Vec3& centre, double radius);  ///< [m]
  ParticleSink& attachTo(const std::string& meshComponent);
  /// A region not attached to a body moves at this constant velocity [m/s] (centre at t = 0).
  ParticleSink& setVelocity(const Vec3& velocity);
  /// Report interval of the server's CSV [s]; unset: the communication interval.
  ParticleSink& setSampleInterval(double seconds);
  [[nodiscard]] v1::ParticleSink& message();

  // Run-time inputs: one-shot, sent with the next package (omitted: unchanged).
  void setEnabled(bool on);             ///< an off sink removes nothing
  void moveTo(const Vec3& centre);      ///< [m], frame as declared

  [[nodiscard]] CountAndMass removedInterval() const;
  [[nodiscard]] CountAndMass removedTotal() const;

 protected:
  void prepareDeclaration() override;
  void writeInputs(v1::DataPackage& package) const override;
  void inputsSent() override;

 private:
  ProtoPtr<v1::ParticleSinkInput> pending_;
};

class PitGenerator : public Component {
 public:
  explicit PitGenerator(std::string name);
  PitGenerator& setMaterial(const std::string& material);
  PitGenerator& setRadius(double metres);                  ///< [m]
  PitGenerator& setRadiusRange(double rMin, double rMax);  ///< [m]
  PitGenerator& setBox(const Vec3& lower, const Vec3& upper);  ///< [m]
  PitGenerator& setTargetHeight(double metres);            ///< bed surface above the floor [m]
  PitGenerator& setSeed(std::uint64_t seed);
  /// Settle clumps of the named ClumpTemplate instead of spheres (then set no sizes).
  PitGenerator& setClumpTemplate(const std::string& templateName);
  /// Group `fraction` [-] of the settled spheres into clods of `radius` [m], joined by the
  /// bonds of the ParallelBonds component `bondsComponent` (docs/reference/pit_generator.md).
  PitGenerator& setClods(double fraction, double radius, const std::string& bondsComponent);
  [[nodiscard]] v1::PitGenerator& message();
};

}  // namespace demlink::client
