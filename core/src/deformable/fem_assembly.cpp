/// See fem_assembly.hpp.
///
/// Shape functions in barycentric coordinates L0..L3 (L1, L2, L3 = the reference coordinates
/// xi, eta, zeta; L0 = 1 - xi - eta - zeta): corners N_i = L_i (2 L_i - 1) (quadratic) or L_i
/// (linear); mid-edge node of edge (i, j): 4 L_i L_j. Strains in Voigt order
/// (xx, yy, zz, 2xy, 2yz, 2zx); isotropic D with Lame lambda = E nu / ((1 + nu)(1 - 2 nu)) and
/// mu = E / (2 (1 + nu)).
#include "demlink/core/deformable/fem_assembly.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>

namespace demlink::core {
namespace {

/// Mid-edge nodes 4..9 (VTK order) and the corners of their edges.
constexpr std::array<std::array<int, 2>, 6> kEdges = {{{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}}};

struct QuadraturePoint {
  std::array<double, 4> l;  ///< barycentric coordinates
  double weight;            ///< reference-tetrahedron weight (the weights sum to 1/6)
};

/// 14-point degree-5 rule (Walkington, "Quadrature on simplices of arbitrary dimension", 2000;
/// checked against the monomial integrals a! b! c! / (a + b + c + 3)! up to degree 5).
std::vector<QuadraturePoint> quadratureRule() {
  std::vector<QuadraturePoint> rule;
  for (const auto& [a, w] : {std::pair{0.0927352503108912, 0.01224884051939366},
                             std::pair{0.3108859192633006, 0.01878132095300264}}) {
    for (int k = 0; k < 4; ++k) {
      std::array<double, 4> l = {a, a, a, a};
      l[static_cast<std::size_t>(k)] = 1.0 - 3.0 * a;
      rule.push_back({l, w});
    }
  }
  const double c = 0.4544962958743504;
  const double d = 0.5 - c;
  for (const auto& e : kEdges) {
    std::array<double, 4> l = {d, d, d, d};
    l[static_cast<std::size_t>(e[0])] = c;
    l[static_cast<std::size_t>(e[1])] = c;
    rule.push_back({l, 0.007091003462846911});
  }
  return rule;
}

/// Shape function values N and derivatives dN/dL (n x 4) at barycentric point l.
void shape(int order, const std::array<double, 4>& l, Eigen::VectorXd& n, Eigen::MatrixXd& dl) {
  const int count = order == 2 ? 10 : 4;
  n.setZero(count);
  dl.setZero(count, 4);
  for (int i = 0; i < 4; ++i) {
    if (order == 2) {
      n[i] = l[static_cast<std::size_t>(i)] * (2.0 * l[static_cast<std::size_t>(i)] - 1.0);
      dl(i, i) = 4.0 * l[static_cast<std::size_t>(i)] - 1.0;
    } else {
      n[i] = l[static_cast<std::size_t>(i)];
      dl(i, i) = 1.0;
    }
  }
  if (order == 2) {
    for (int m = 0; m < 6; ++m) {
      const auto [a, b] = kEdges[static_cast<std::size_t>(m)];
      n[4 + m] = 4.0 * l[static_cast<std::size_t>(a)] * l[static_cast<std::size_t>(b)];
      dl(4 + m, a) = 4.0 * l[static_cast<std::size_t>(b)];
      dl(4 + m, b) = 4.0 * l[static_cast<std::size_t>(a)];
    }
  }
}

Eigen::Matrix<double, 6, 6> elasticity(const ElasticMaterial& m) {
  const double nu = m.poisson_ratio;
  const double lambda = m.youngs_modulus * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  const double mu = m.youngs_modulus / (2.0 * (1.0 + nu));
  Eigen::Matrix<double, 6, 6> d = Eigen::Matrix<double, 6, 6>::Zero();
  d.topLeftCorner<3, 3>().setConstant(lambda);
  for (int i = 0; i < 3; ++i) {
    d(i, i) += 2.0 * mu;
    d(3 + i, 3 + i) = mu;
  }
  return d;
}

/// Element geometry at one point: B (6 x 3n), N, det J.
struct PointData {
  Eigen::MatrixXd b;
  Eigen::VectorXd n;
  double detJ = 0.0;
};

PointData pointData(const TetMesh& mesh, std::size_t element, const std::array<double, 4>& l) {
  const std::size_t npt = mesh.nodesPerTet();
  const std::uint32_t* t = &mesh.tets[element * npt];
  PointData p;
  Eigen::MatrixXd dl;
  shape(mesh.order, l, p.n, dl);
  // dN/dxi_j = dN/dL_j - dN/dL_0 (j = 1..3).
  Eigen::MatrixXd dxi(static_cast<Eigen::Index>(npt), 3);
  for (int j = 0; j < 3; ++j) dxi.col(j) = dl.col(j + 1) - dl.col(0);
  Eigen::Matrix3d jac = Eigen::Matrix3d::Zero();  // J(i, j) = d x_i / d xi_j
  for (std::size_t a = 0; a < npt; ++a) jac += mesh.nodes[t[a]] * dxi.row(static_cast<Eigen::Index>(a));
  p.detJ = jac.determinant();
  const Eigen::MatrixXd dx = dxi * jac.inverse();  // dN_a/dx_i
  p.b.setZero(6, static_cast<Eigen::Index>(3 * npt));
  for (std::size_t a = 0; a < npt; ++a) {
    const auto ai = static_cast<Eigen::Index>(a);
    const auto c = static_cast<Eigen::Index>(3 * a);
    p.b(0, c) = dx(ai, 0);
    p.b(1, c + 1) = dx(ai, 1);
    p.b(2, c + 2) = dx(ai, 2);
    p.b(3, c) = dx(ai, 1);
    p.b(3, c + 1) = dx(ai, 0);
    p.b(4, c + 1) = dx(ai, 2);
    p.b(4, c + 2) = dx(ai, 1);
    p.b(5, c) = dx(ai, 2);
    p.b(5, c + 2) = dx(ai, 0);
  }
  return p;
}

}  // namespace

FemMatrices assembleTetMesh(const TetMesh& mesh, const ElasticMaterial& material, bool lumpedMass) {
  const std::size_t npt = mesh.nodesPerTet();
  const auto ndof = static_cast<Eigen::Index>(3 * mesh.nodes.size());
  const Eigen::Matrix<double, 6, 6> d = elasticity(material);
  const std::vector<QuadraturePoint> rule = quadratureRule();
  std::vector<Eigen::Triplet<double>> kTriplets;
  std::vector<Eigen::Triplet<double>> mTriplets;
  kTriplets.reserve(mesh.tetCount() * 9 * npt * npt);
  mTriplets.reserve(mesh.tetCount() * (lumpedMass ? 3 * npt : 3 * npt * npt));
  Eigen::MatrixXd ke(3 * npt, 3 * npt);
  Eigen::MatrixXd me(npt, npt);  // scalar mass (the same for x, y, z)
  for (std::size_t e = 0; e < mesh.tetCount(); ++e) {
    ke.setZero();
    me.setZero();
    for (const QuadraturePoint& q : rule) {
      const PointData p = pointData(mesh, e, q.l);
      const double w = q.weight * p.detJ;
      ke.noalias() += w * p.b.transpose() * d * p.b;
      me.noalias() += (w * material.density) * p.n * p.n.transpose();
    }
    const std::uint32_t* t = &mesh.tets[e * npt];
    for (std::size_t a = 0; a < npt; ++a) {
      for (std::size_t b = 0; b < npt; ++b) {
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) {
            kTriplets.emplace_back(
                static_cast<int>(3 * t[a]) + i, static_cast<int>(3 * t[b]) + j,
                ke(static_cast<Eigen::Index>(3 * a) + i, static_cast<Eigen::Index>(3 * b) + j));
          }
        }
      }
    }
    if (lumpedMass) {
      const double elementMass = me.sum();
      Eigen::VectorXd lumped =
          mesh.order == 1 ? Eigen::VectorXd(me.rowwise().sum()) : Eigen::VectorXd(me.diagonal());
      lumped *= elementMass / lumped.sum();
      for (std::size_t a = 0; a < npt; ++a) {
        for (int i = 0; i < 3; ++i)
          mTriplets.emplace_back(static_cast<int>(3 * t[a]) + i, static_cast<int>(3 * t[a]) + i,
                                 lumped[static_cast<Eigen::Index>(a)]);
      }
    } else {
      for (std::size_t a = 0; a < npt; ++a) {
        for (std::size_t b = 0; b < npt; ++b) {
          for (int i = 0; i < 3; ++i) {
            mTriplets.emplace_back(static_cast<int>(3 * t[a]) + i, static_cast<int>(3 * t[b]) + i,
                                   me(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)));
          }
        }
      }
    }
  }
  FemMatrices out;
  out.stiffness.resize(ndof, ndof);
  out.stiffness.setFromTriplets(kTriplets.begin(), kTriplets.end());
  out.mass.resize(ndof, ndof);
  out.mass.setFromTriplets(mTriplets.begin(), mTriplets.end());
  return out;
}

std::vector<double> vonMisesAtCentroids(const TetMesh& mesh, const ElasticMaterial& material,
                                        const Eigen::VectorXd& u) {
  const std::size_t npt = mesh.nodesPerTet();
  const Eigen::Matrix<double, 6, 6> d = elasticity(material);
  std::vector<double> out(mesh.tetCount());
  Eigen::VectorXd ue(static_cast<Eigen::Index>(3 * npt));
  for (std::size_t e = 0; e < mesh.tetCount(); ++e) {
    const PointData p = pointData(mesh, e, {0.25, 0.25, 0.25, 0.25});
    for (std::size_t a = 0; a < npt; ++a) {
      ue.segment<3>(static_cast<Eigen::Index>(3 * a)) =
          u.segment<3>(3 * static_cast<Eigen::Index>(mesh.tets[e * npt + a]));
    }
    const Eigen::Matrix<double, 6, 1> s = d * (p.b * ue);
    out[e] = std::sqrt(0.5 * ((s[0] - s[1]) * (s[0] - s[1]) + (s[1] - s[2]) * (s[1] - s[2]) +
                              (s[2] - s[0]) * (s[2] - s[0])) +
                       3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
  }
  return out;
}

double largestEigenvalue(const Eigen::SparseMatrix<double>& stiffness, const Eigen::VectorXd& massDiagonal) {
  const Eigen::Index n = massDiagonal.size();
  if (n == 0) return 0.0;
  const Eigen::VectorXd scale = massDiagonal.cwiseSqrt().cwiseInverse();
  Eigen::VectorXd v(n);
  // Deterministic, not smooth: excites the highest modes as well as the lowest.
  for (Eigen::Index i = 0; i < n; ++i) v[i] = 1.0 + 0.5 * std::sin(12.9898 * static_cast<double>(i) + 0.7);
  v.normalize();
  Eigen::VectorXd previous = Eigen::VectorXd::Zero(n);
  std::vector<double> alpha;
  std::vector<double> beta;
  double lambda = 0.0;
  double betaPrev = 0.0;
  const Eigen::Index steps = std::min<Eigen::Index>(n, 400);
  for (Eigen::Index k = 0; k < steps; ++k) {
    Eigen::VectorXd w = scale.cwiseProduct(stiffness * scale.cwiseProduct(v));
    const double a = w.dot(v);
    w -= a * v + betaPrev * previous;
    alpha.push_back(a);
    const double b = w.norm();
    if ((k + 1) % 10 == 0 || k + 1 == steps || b <= 1e-14 * std::abs(a)) {
      const auto m = static_cast<Eigen::Index>(alpha.size());
      Eigen::MatrixXd t = Eigen::MatrixXd::Zero(m, m);
      for (Eigen::Index i = 0; i < m; ++i) {
        t(i, i) = alpha[static_cast<std::size_t>(i)];
        if (i + 1 < m) t(i, i + 1) = t(i + 1, i) = beta[static_cast<std::size_t>(i)];
      }
      const double next =
          Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(t, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
      const bool converged = std::abs(next - lambda) <= 1e-12 * std::abs(next);
      lambda = next;
      if (converged || b <= 1e-14 * std::abs(a)) break;
    }
    beta.push_back(b);
    previous = v;
    v = w / b;
    betaPrev = b;
  }
  return lambda;
}

}  // namespace demlink::core
