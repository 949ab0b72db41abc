#pragma once
/// Principal moments and axes of an inertia tensor, with the one sign convention every
/// frame derived from an inertia uses (clump templates, solids read from STL), so two
/// computations of the same body give the same axes.
#include <Eigen/Eigenvalues>

#include "demlink/core/base/math_types.hpp"

namespace demlink::core {

struct PrincipalAxes {
  Vec3 moments = Vec3::Zero();  ///< ascending, in the unit of the tensor
  Mat3 axes = Mat3::Identity(); ///< column k: unit axis of moments[k]; largest component positive, right-handed
};

/// Eigen-decomposition of a symmetric inertia tensor (Eigen::SelfAdjointEigenSolver).
[[nodiscard]] inline PrincipalAxes principalAxes(const Mat3& inertia) {
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(inertia);
  PrincipalAxes out;
  out.moments = solver.eigenvalues();
  out.axes = solver.eigenvectors();
  for (int col = 0; col < 3; ++col) {
    Eigen::Index largest = 0;
    out.axes.col(col).cwiseAbs().maxCoeff(&largest);
    if (out.axes(largest, col) < 0.0) out.axes.col(col) *= -1.0;
  }
  if (out.axes.determinant() < 0.0) out.axes.col(2) *= -1.0;
  return out;
}

}  // namespace demlink::core
