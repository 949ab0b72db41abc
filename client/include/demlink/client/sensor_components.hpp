#pragma once
/// Measuring components: RegionSensor (count, mass, centre of mass, mean velocity inside
/// a box or sphere, and the parallel bonds there), FlowSensor (crossings of a rectangle or disc per direction) and
/// ParticleView (decimated positions for a 3D view, the coupling paper's DEMPoints).
///
/// Why sensors fill their sample interval: the schema requires one for the server's CSV
/// reports, and a coupled client almost always wants those at its communication interval;
/// an explicit setSampleInterval() wins.
#include <cstdint>
#include <string>
#include <vector>

#include "demlink/client/component.hpp"

namespace demlink::client {

class RegionSensor : public Component {
 public:
  explicit RegionSensor(std::string name);
  RegionSensor& setBox(const Vec3& centre, const Vec3& size, const Quat& orientation = {});  ///< [m]
  RegionSensor& setSphere(const Vec3& centre, double radius);  ///< [m]
  /// Follow a rigid/mesh body; centre and orientation are then in its frame.
  RegionSensor& attachTo(const std::string& bodyComponent);
  /// A region not attached to a body moves at this constant velocity [m/s]; `centre` is
  /// then where it is at t = 0.
  RegionSensor& setVelocity(const Vec3& velocity);
  RegionSensor& setSampleInterval(double seconds);  ///< [s]
  [[nodiscard]] v1::RegionSensor& message();

  // Run-time inputs: one-shot, sent with the next package; the server applies them from
  // that package's step on (omitted: unchanged). Frame as declared (world or the body's).
  void moveTo(const Vec3& centre);          ///< [m]
  void turnTo(const Quat& orientation);     ///< box axes [-]
  void resizeBox(const Vec3& size);         ///< side lengths [m] (box only)
  void resizeSphere(double radius);         ///< [m] (sphere only)

  [[nodiscard]] std::uint64_t count() const;   ///< particles inside [-]
  [[nodiscard]] double mass() const;           ///< [kg]
  [[nodiscard]] Vec3 centreOfMass() const;     ///< [m]; zero when empty (count() == 0)
  [[nodiscard]] Vec3 meanVelocity() const;     ///< mass-weighted [m/s]; zero when empty
  /// Parallel bonds whose midpoint is inside, intact and broken [-] (0 without bonds).
  [[nodiscard]] std::uint64_t bondsIntact() const;
  [[nodiscard]] std::uint64_t bondsBroken() const;

 protected:
  void prepareDeclaration() override;
  void writeInputs(v1::DataPackage& package) const override;
  void inputsSent() override;

 private:
  v1::RegionInput& pending();
  ProtoPtr<v1::RegionInput> pending_;
};

class FlowSensor : public Component {
 public:
  explicit FlowSensor(std::string name);
  /// Rectangle length x width [m] with positive flow along `normal`.
  FlowSensor& setRectangle(const Vec3& centre, const Vec3& normal, double length, double width,
                           const Vec3& lengthAxis = {});
  FlowSensor& setDisc(const Vec3& centre, const Vec3& normal, double radius);  ///< [m]
  FlowSensor& attachTo(const std::string& bodyComponent);
  /// A surface not attached to a body moves at this constant velocity [m/s] (centre at t = 0).
  FlowSensor& setVelocity(const Vec3& velocity);
  FlowSensor& setSampleInterval(double seconds);  ///< [s]
  [[nodiscard]] v1::FlowSensor& message();

  [[nodiscard]] CountAndMass positiveInterval() const;  ///< along the normal, latest interval
  [[nodiscard]] CountAndMass negativeInterval() const;
  [[nodiscard]] CountAndMass positiveTotal() const;     ///< since step 0
  [[nodiscard]] CountAndMass negativeTotal() const;

 protected:
  void prepareDeclaration() override;
};

class ParticleView : public Component {
 public:
  explicit ParticleView(std::string name);
  ParticleView& setMaxCount(std::uint32_t count);  ///< particles per package [-]; 0: 10000
  [[nodiscard]] v1::ParticleView& message();

  [[nodiscard]] std::uint64_t totalCount() const;  ///< particles in the world [-]
  /// Particles whose id is a multiple of stride() are listed, in increasing id order [-].
  [[nodiscard]] std::uint32_t stride() const;
  [[nodiscard]] std::vector<Vec3> positions() const;   ///< [m]
  [[nodiscard]] std::vector<Vec3> velocities() const;  ///< [m/s]
  [[nodiscard]] std::vector<std::uint64_t> ids() const;
  [[nodiscard]] const v1::ParticleViewOutput& view() const;
};

}  // namespace demlink::client
