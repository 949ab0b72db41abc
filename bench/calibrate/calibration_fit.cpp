#include "calibration_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>

namespace demlink::calibrate {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

/// Parameters in the unit box: u = (p - min) / (max - min).
struct UnitBox {
  std::vector<Bounds> bounds;
  [[nodiscard]] std::vector<double> toParameters(const VectorXd& u) const {
    std::vector<double> p(bounds.size());
    for (std::size_t j = 0; j < p.size(); ++j) p[j] = bounds[j].min + u[static_cast<Eigen::Index>(j)] * width(j);
    return p;
  }
  [[nodiscard]] VectorXd toUnit(const std::vector<double>& p) const {
    VectorXd u(static_cast<Eigen::Index>(p.size()));
    for (std::size_t j = 0; j < p.size(); ++j) u[static_cast<Eigen::Index>(j)] = (p[j] - bounds[j].min) / width(j);
    return u;
  }
  [[nodiscard]] double width(std::size_t j) const { return bounds[j].max - bounds[j].min; }
};

/// The quadratic basis 1, u_j, u_j u_k (j <= k).
VectorXd basis(const VectorXd& u) {
  const Eigen::Index n = u.size();
  VectorXd b(1 + n + n * (n + 1) / 2);
  Eigen::Index k = 0;
  b[k++] = 1.0;
  for (Eigen::Index j = 0; j < n; ++j) b[k++] = u[j];
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index l = j; l < n; ++l) b[k++] = u[j] * u[l];
  }
  return b;
}

/// d basis / d u_j.
VectorXd basisDerivative(const VectorXd& u, Eigen::Index j) {
  const Eigen::Index n = u.size();
  VectorXd b = VectorXd::Zero(1 + n + n * (n + 1) / 2);
  Eigen::Index k = 1 + n;
  b[1 + j] = 1.0;
  for (Eigen::Index a = 0; a < n; ++a) {
    for (Eigen::Index c = a; c < n; ++c, ++k) {
      if (a == j) b[k] += u[c];
      if (c == j) b[k] += u[a];
    }
  }
  return b;
}

/// A quadratic per response, fitted by weighted least squares.
struct Surface {
  std::vector<VectorXd> coefficients;  ///< one per response

  [[nodiscard]] std::vector<double> at(const VectorXd& u) const {
    const VectorXd b = basis(u);
    std::vector<double> out;
    for (const VectorXd& c : coefficients) out.push_back(c.dot(b));
    return out;
  }
};

Surface fitSurface(const std::vector<VectorXd>& points, const std::vector<std::vector<double>>& responses,
                   const std::vector<double>& weights) {
  const auto rows = static_cast<Eigen::Index>(points.size());
  const Eigen::Index terms = basis(points.front()).size();
  MatrixXd a(rows, terms);
  for (Eigen::Index r = 0; r < rows; ++r) {
    a.row(r) = std::sqrt(weights[static_cast<std::size_t>(r)]) * basis(points[static_cast<std::size_t>(r)]).transpose();
  }
  const Eigen::ColPivHouseholderQR<MatrixXd> qr(a);
  Surface surface;
  for (std::size_t m = 0; m < responses.front().size(); ++m) {
    VectorXd y(rows);
    for (Eigen::Index r = 0; r < rows; ++r) {
      y[r] = std::sqrt(weights[static_cast<std::size_t>(r)]) * responses[static_cast<std::size_t>(r)][m];
    }
    surface.coefficients.push_back(qr.solve(y));
  }
  return surface;
}

/// The minimum of the surfaces' misfit over the unit box: a grid, then a grid 20 times
/// finer over the cells around its best point.
VectorXd minimise(const Surface& surface, const std::vector<double>& targets, Eigen::Index n) {
  const int cells = n == 1 ? 200 : n == 2 ? 50 : 20;
  VectorXd best = VectorXd::Constant(n, 0.5);
  double bestValue = std::numeric_limits<double>::infinity();
  auto scan = [&](const VectorXd& lo, const VectorXd& hi, int steps) {
    std::vector<int> index(static_cast<std::size_t>(n), 0);
    while (true) {
      VectorXd u(n);
      for (Eigen::Index j = 0; j < n; ++j) {
        u[j] = lo[j] + (hi[j] - lo[j]) * index[static_cast<std::size_t>(j)] / steps;
      }
      const double value = relativeMisfit(surface.at(u), targets);
      if (value < bestValue) {
        bestValue = value;
        best = u;
      }
      Eigen::Index j = 0;
      while (j < n && ++index[static_cast<std::size_t>(j)] > steps) index[static_cast<std::size_t>(j++)] = 0;
      if (j == n) break;
    }
  };
  scan(VectorXd::Zero(n), VectorXd::Ones(n), cells);
  const double cell = 1.0 / cells;
  scan((best.array() - cell).max(0.0).matrix(), (best.array() + cell).min(1.0).matrix(), 20);
  return best;
}

/// The first design: 5 levels for one parameter, the 3 x 3 grid for two, the face-centred
/// composite design (centre, face centres, corners) for three.
std::vector<VectorXd> firstDesign(Eigen::Index n) {
  std::vector<VectorXd> out;
  if (n == 1) {
    for (double u : {0.0, 0.25, 0.5, 0.75, 1.0}) out.push_back(VectorXd::Constant(1, u));
  } else if (n == 2) {
    for (double a : {0.0, 0.5, 1.0}) {
      for (double b : {0.0, 0.5, 1.0}) out.push_back((VectorXd(2) << a, b).finished());
    }
  } else {
    out.push_back(VectorXd::Constant(3, 0.5));
    for (Eigen::Index j = 0; j < 3; ++j) {
      for (double v : {0.0, 1.0}) {
        VectorXd u = VectorXd::Constant(3, 0.5);
        u[j] = v;
        out.push_back(u);
      }
    }
    for (int corner = 0; corner < 8; ++corner) {
      VectorXd u(3);
      for (Eigen::Index j = 0; j < 3; ++j) u[j] = (corner >> j) & 1 ? 1.0 : 0.0;
      out.push_back(u);
    }
  }
  return out;
}

}  // namespace

double relativeMisfit(const std::vector<double>& responses, const std::vector<double>& targets) {
  double sum = 0.0;
  for (std::size_t m = 0; m < targets.size(); ++m) {
    const double r = (responses[m] - targets[m]) / targets[m];
    sum += r * r;
  }
  return sum;
}

FitResult fitParameters(const std::vector<Bounds>& bounds, const std::vector<double>& targets,
                        const Evaluate& evaluate, const FitOptions& options) {
  if (bounds.empty() || bounds.size() > 3) throw std::invalid_argument("fitParameters: 1 to 3 parameters");
  if (targets.size() < bounds.size()) throw std::invalid_argument("fitParameters: fewer targets than parameters");
  const UnitBox box{bounds};
  const auto n = static_cast<Eigen::Index>(bounds.size());
  FitResult result;
  std::vector<VectorXd> points;
  std::vector<std::vector<double>> responses;
  std::size_t planned = 0;
  auto run = [&](const std::vector<VectorXd>& design) {
    std::vector<VectorXd> fresh;
    for (const VectorXd& u : design) {
      const bool seen = std::any_of(points.begin(), points.end(), [&](const VectorXd& p) { return (p - u).norm() < 1e-9; }) ||
                        std::any_of(fresh.begin(), fresh.end(), [&](const VectorXd& p) { return (p - u).norm() < 1e-9; });
      if (!seen) fresh.push_back(u);
    }
    planned += fresh.size();
    for (const VectorXd& u : fresh) {
      const std::vector<double> p = box.toParameters(u);
      if (options.progress) options.progress(points.size(), planned, p);
      std::vector<double> r = evaluate(p);
      if (r.size() != targets.size()) throw std::logic_error("fitParameters: Evaluate returned the wrong count");
      points.push_back(u);
      responses.push_back(r);
      result.evaluations.push_back({p, std::move(r)});
    }
  };

  run(firstDesign(n));
  std::vector<double> weights(points.size(), 1.0);
  Surface surface = fitSurface(points, responses, weights);
  VectorXd centre = minimise(surface, targets, n);
  double half = 0.5;
  for (int round = 0; round < options.refinements; ++round) {
    half *= 0.5;
    std::vector<VectorXd> design{centre};
    for (Eigen::Index j = 0; j < n; ++j) {
      for (double sign : {-1.0, 1.0}) {
        VectorXd u = centre;
        u[j] = std::clamp(u[j] + sign * half, 0.0, 1.0);
        design.push_back(u);
      }
    }
    run(design);
    weights.assign(points.size(), 1.0);
    for (std::size_t k = 0; k < points.size(); ++k) {
      const double d = (points[k] - centre).cwiseAbs().maxCoeff();
      if (d > half * (1.0 + 1e-9)) weights[k] = (half / d) * (half / d);
    }
    surface = fitSurface(points, responses, weights);
    centre = minimise(surface, targets, n);
  }

  result.parameters = box.toParameters(centre);
  result.predicted = surface.at(centre);
  for (std::size_t m = 0; m < targets.size(); ++m) {
    std::vector<double> row;
    for (Eigen::Index j = 0; j < n; ++j) {
      row.push_back(surface.coefficients[m].dot(basisDerivative(centre, j)) / box.width(static_cast<std::size_t>(j)));
    }
    result.slopes.push_back(std::move(row));
  }
  for (Eigen::Index j = 0; j < n; ++j) result.at_bound.push_back(centre[j] < 1e-3 || centre[j] > 1.0 - 1e-3);
  return result;
}

std::vector<double> parameterUncertainty(const std::vector<std::vector<double>>& slopes,
                                         const std::vector<double>& scatter) {
  const auto m = static_cast<Eigen::Index>(slopes.size());
  const auto n = static_cast<Eigen::Index>(slopes.front().size());
  MatrixXd weighted(m, n);
  for (Eigen::Index i = 0; i < m; ++i) {
    const double s = std::max(scatter[static_cast<std::size_t>(i)], std::numeric_limits<double>::min());
    for (Eigen::Index j = 0; j < n; ++j) {
      weighted(i, j) = slopes[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] / s;
    }
  }
  const MatrixXd information = weighted.transpose() * weighted;
  const Eigen::FullPivLU<MatrixXd> lu(information);
  std::vector<double> sigma(static_cast<std::size_t>(n), std::nan(""));
  if (lu.rank() < n) return sigma;
  const MatrixXd covariance = lu.inverse();
  for (Eigen::Index j = 0; j < n; ++j) sigma[static_cast<std::size_t>(j)] = std::sqrt(covariance(j, j));
  return sigma;
}

}  // namespace demlink::calibrate
