#pragma once
/// Linear-algebra vocabulary of the engine. Eigen's fixed-size types are used
/// directly: Vec3 is 24 bytes (three doubles, no padding), so arrays of Vec3 are
/// tightly packed structure-of-arrays columns.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace demlink::core {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using Mat3 = Eigen::Matrix3d;

}  // namespace demlink::core
