#pragma once
/// Stiffness and mass matrices of isotropic linear-elastic tetrahedra (4-node linear, 10-node
/// quadratic), assembled into sparse matrices with 3 DOF per node (x, y, z of node i are
/// DOFs 3i, 3i+1, 3i+2).
///
/// Element integrals use the 14-point degree-5 rule on the tetrahedron (positive weights), exact
/// for the quadratic element's mass (degree 4) and stiffness (degree 2) on straight-sided
/// elements. Lumped mass: row sums for linear elements (rho V / 4 per corner); for quadratic
/// elements the row sums are zero or negative at the corners, so the HRZ scaling is used
/// instead (Hinton, Rock, Zienkiewicz, "A note on mass lumping and related processes in the
/// finite element method", 1976): the diagonal of the consistent element mass, scaled so that it
/// sums to the element's mass.
#include <Eigen/SparseCore>
#include <vector>

#include "demlink/core/deformable/tet_mesh.hpp"

namespace demlink::core {

struct ElasticMaterial {
  double youngs_modulus = 0.0;  ///< [Pa]
  double poisson_ratio = 0.0;
  double density = 0.0;  ///< [kg/m^3]
};

struct FemMatrices {
  Eigen::SparseMatrix<double> stiffness;  ///< [N/m]
  Eigen::SparseMatrix<double> mass;       ///< [kg]; diagonal when lumped
};

/// Assembles K and M (lumped or consistent) over all tetrahedra of `mesh`.
[[nodiscard]] FemMatrices assembleTetMesh(const TetMesh& mesh, const ElasticMaterial& material,
                                          bool lumpedMass);

/// Von Mises stress [Pa] of each element at its centroid for the displacements `u` [m].
[[nodiscard]] std::vector<double> vonMisesAtCentroids(const TetMesh& mesh, const ElasticMaterial& material,
                                                      const Eigen::VectorXd& u);

/// Largest eigenvalue omega^2 [1/s^2] of K x = omega^2 M x for a diagonal M given as
/// `massDiagonal` (all > 0), by Lanczos iteration on M^-1/2 K M^-1/2 (no reorthogonalisation:
/// the largest Ritz value converges from below and is not disturbed by the loss of
/// orthogonality). Deterministic start vector.
[[nodiscard]] double largestEigenvalue(const Eigen::SparseMatrix<double>& stiffness,
                                       const Eigen::VectorXd& massDiagonal);

}  // namespace demlink::core
