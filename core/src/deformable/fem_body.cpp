/// Linear FEM body (fem_body.hpp): M U'' + C U' + K U = F on the free DOFs, the fixed and
/// driven DOFs prescribed.
///
/// Three-level scheme. The three-point recurrence of the Newmark family with gamma = 1/2
/// (Zienkiewicz, "A new look at the Newmark, Houbolt and other time stepping formulas", 1977):
///   M (U+ - 2U + U-)/dt^2 + C (U+ - U-)/(2 dt) + K (b U+ + (1 - 2b) U + b U-)
///       = b F+ + (1 - 2b) F + b F-,
/// here with b = 1/3, i.e. A1 U+ = (F+ + F + F-)/3 + A3 U + A4 U- with
///   A1 = M/dt^2 + C/(2 dt) + K/3,   A3 = 2M/dt^2 - K/3,   A4 = -(M/dt^2 - C/(2 dt) + K/3).
/// The solver paper (BMEDEM3D, its eq. 21) prints A4 = M/dt^2 + C/(2 dt) - K/3: the sign of its
/// M term is wrong (A4 = -M/dt^2 + C/(2 dt) - K/3). With the printed sign the undamped scalar
/// recurrence has a root above 1 at any step (for small Omega, z^2 - 2z - 1 = 0, z = 1 + sqrt 2),
/// so every motion grows; the energy test fails at its first step with it. Stability: for one undamped mode,
/// Omega = omega dt, the characteristic equation is
///   (1 + b Omega^2) z^2 - (2 - (1 - 2b) Omega^2) z + (1 + b Omega^2) = 0;
/// the product of its roots is 1 and they are complex for every Omega when b >= 1/4, so
/// |z| = 1 exactly (spectral radius 1, no growth, no numerical damping) at any step; Rayleigh
/// damping only moves the roots inside. A1 is factorised once (sparse Cholesky, below).
///
/// Loads. F+ (the contact forces at the new positions) is not known when U+ is solved for;
/// the latest contact forces stand in for it (a one-step lag: F+ := F), so the right-hand side
/// uses (2 F + F-)/3. Gravity (M g) is exact. The reaction at the prescribed DOFs is the
/// residual of the same equation on those rows with the true F+, once endStep has it.
///
/// Central differences (lumped M): U+ = 2U - U- + dt^2 M^-1 (F - K U - C (U - U-)/dt), the
/// damping force from the backward velocity so the step stays explicit. Stable while
/// omega_max^2 dt^2 + 2 (beta + alpha omega_max^2) dt < 4 (Jury's conditions on the scalar
/// recurrence; 2/omega_max undamped), omega_max from Lanczos iteration on the free DOFs.
///
/// Velocities (surface, kinetic energy): (3U+ - 4U + U-)/(2 dt), second order at the new time
/// level; driven nodes take the twist of the driving pose, fixed nodes 0. Driven nodes: beginStep
/// carries the pose by its twist to t + dt (NodeConstraints::advance, as the mass-spring body
/// does) and prescribes U+ there.
#include "demlink/core/deformable/fem_body.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#ifdef DEMLINK_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#include <cmath>
#include <limits>

#include "demlink/core/deformable/fem_assembly.hpp"
#include "demlink/core/deformable/fem_input_files.hpp"
#include "demlink/core/deformable/gmsh_reader.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/state/state_stream.hpp"

namespace demlink::core {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Eigen::VectorXd;

// The factorisation of A1 (three-level scheme) and of K (solveStatic). CHOLMOD's supernodal
// Cholesky with its own ordering (the better of AMD and METIS nested dissection) keeps the fill
// of stocky 3D meshes bounded where Eigen's simplicial LDL^T with AMD does not (docs/deformable.md,
// "Cost"); without SuiteSparse the build falls back to the latter.
#ifdef DEMLINK_HAVE_CHOLMOD
using Factorisation = Eigen::CholmodSupernodalLLT<SparseMatrix>;
bool positiveDefinite(const Factorisation& f, Eigen::Index) { return f.info() == Eigen::Success; }
#else
using Factorisation = Eigen::SimplicialLDLT<SparseMatrix>;
bool positiveDefinite(const Factorisation& f, Eigen::Index size) {
  return f.info() == Eigen::Success && (size == 0 || f.vectorD().minCoeff() > 0.0);
}
#endif

namespace {

/// Renumbers DOFs: new DOF 3 newOf[n] + i for old DOF 3 n + i.
SparseMatrix permuted(const SparseMatrix& a, const std::vector<std::uint32_t>& newOf) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(a.nonZeros()));
  const auto map = [&](Eigen::Index dof) {
    return static_cast<int>(3 * newOf[static_cast<std::size_t>(dof / 3)] +
                            static_cast<std::uint32_t>(dof % 3));
  };
  for (int c = 0; c < a.outerSize(); ++c) {
    for (SparseMatrix::InnerIterator it(a, c); it; ++it)
      t.emplace_back(map(it.row()), map(it.col()), it.value());
  }
  SparseMatrix out(a.rows(), a.cols());
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

/// Rows `rows` of `a` (in that order) as a rows.size() x a.cols() matrix.
SparseMatrix selectRows(const SparseMatrix& a, const std::vector<std::uint32_t>& rows) {
  SparseMatrix s(static_cast<Eigen::Index>(rows.size()), a.rows());
  std::vector<Eigen::Triplet<double>> t;
  for (std::size_t i = 0; i < rows.size(); ++i)
    t.emplace_back(static_cast<int>(i), static_cast<int>(rows[i]), 1.0);
  s.setFromTriplets(t.begin(), t.end());
  return s * a;
}

/// Block `dofs` x `dofs` of `a`, given the position of each DOF in `dofs` (-1 if absent).
SparseMatrix block(const SparseMatrix& a, const std::vector<std::int32_t>& indexOf, std::size_t size) {
  std::vector<Eigen::Triplet<double>> t;
  for (int c = 0; c < a.outerSize(); ++c) {
    const std::int32_t j = indexOf[static_cast<std::size_t>(c)];
    if (j < 0) continue;
    for (SparseMatrix::InnerIterator it(a, c); it; ++it) {
      const std::int32_t i = indexOf[static_cast<std::size_t>(it.row())];
      if (i >= 0) t.emplace_back(i, j, it.value());
    }
  }
  SparseMatrix out(static_cast<Eigen::Index>(size), static_cast<Eigen::Index>(size));
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

std::vector<double> toStd(const VectorXd& v) { return {v.data(), v.data() + v.size()}; }

VectorXd fromStd(StateReader& in, const std::vector<double>& v, Eigen::Index size, const std::string& what) {
  requireEqual(in, what + " length " + std::to_string(v.size()), static_cast<Eigen::Index>(v.size()), size);
  return Eigen::Map<const VectorXd>(v.data(), size);
}

}  // namespace

struct FemBody::Impl {
  std::string name;
  std::string prefix;
  FemIntegrator integrator = FemIntegrator::kThreeLevel;
  double dt = 0.0;
  double alpha = 0.0;
  double beta = 0.0;

  // Geometry (body node order: surface nodes first).
  TetMesh mesh;  // empty for imported matrices
  bool assembled = false;
  ElasticMaterial material;
  std::vector<std::vector<std::uint32_t>> elements;
  VectorXd x0;  // reference positions [m], 3 per node
  DeformableSurface surface;

  // Matrices.
  SparseMatrix k;
  SparseMatrix m;
  SparseMatrix c;  // explicit damping matrix; empty: Rayleigh
  bool explicitDamping = false;
  double mass = 0.0;

  // Constraints.
  NodeConstraints constraints;
  std::vector<std::uint32_t> freeDofs;
  std::vector<std::uint32_t> fixedDofs;
  std::vector<std::uint32_t> drivenDofs;
  std::vector<std::int32_t> freeIndex;                             // per DOF: position in freeDofs or -1
  SparseMatrix kFixed, mFixed, cFixed, kDriven, mDriven, cDriven;  // rows of K, M, C

  // Integrator.
  Factorisation a1;
  VectorXd lumpedFree;  // central differences: M diagonal on the free DOFs
  double omegaMax = 0.0;

  // State: displacements at the three time levels, velocity, contact loads at the last two.
  VectorXd u, u1, u2, v, fc1, fc0;
  Vec3 gravity = Vec3::Zero();
  VectorXd gravityLoad;

  [[nodiscard]] std::size_t nodes() const { return static_cast<std::size_t>(x0.size() / 3); }
  [[nodiscard]] Vec3 at(const VectorXd& a, std::size_t node) const {
    return a.segment<3>(3 * static_cast<Eigen::Index>(node));
  }

  /// M a - K b + C d with one product by K and one by M when C is Rayleigh.
  [[nodiscard]] VectorXd combine(const VectorXd& a, const VectorXd& b, const VectorXd& d) const {
    if (explicitDamping) return m * a - k * b + c * d;
    return m * (a + beta * d) - k * (b - alpha * d);
  }

  void buildFromMesh(const FemSpec& spec);
  void buildFromMatrices(const FemSpec& spec);
  void renumber(std::vector<Vec3>& nodes, std::vector<std::array<std::uint32_t, 3>>& triangles,
                std::vector<std::uint32_t>& newOf);
  void constrain(const FemSpec& spec, const std::vector<std::uint32_t>& newOf,
                 const std::vector<std::uint64_t>& inputIds);
  void factorise();
  void prescribe(VectorXd& target, VectorXd* velocity) const;
  void updateGravity(const Vec3& g);
  [[nodiscard]] VectorXd contactLoad() const;
  void writeSurface();
  NodeReaction reaction(const std::vector<std::uint32_t>& dofs, const VectorXd& r, const Vec3& about) const;
};

// ---------------------------------------------------------------------------------------------
// Building

void FemBody::Impl::renumber(std::vector<Vec3>& nodes, std::vector<std::array<std::uint32_t, 3>>& triangles,
                             std::vector<std::uint32_t>& newOf) {
  newOf.assign(nodes.size(), UINT32_MAX);
  std::uint32_t next = 0;
  for (const auto& t : triangles) {
    for (const std::uint32_t n : t) {
      if (newOf[n] == UINT32_MAX) newOf[n] = next++;
    }
  }
  const std::uint32_t surfaceNodes = next;
  for (auto& n : newOf) {
    if (n == UINT32_MAX) n = next++;
  }
  std::vector<Vec3> reordered(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) reordered[newOf[i]] = nodes[i];
  nodes = std::move(reordered);
  for (auto& t : triangles) {
    for (auto& n : t) n = newOf[n];
  }
  x0.resize(3 * static_cast<Eigen::Index>(nodes.size()));
  for (std::size_t i = 0; i < nodes.size(); ++i) x0.segment<3>(3 * static_cast<Eigen::Index>(i)) = nodes[i];
  surface = DeformableSurface(surfaceNodes, triangles, 0, prefix);
}

void FemBody::Impl::buildFromMesh(const FemSpec& spec) {
  requirePositive(prefix + ".youngs_modulus", spec.youngs_modulus);
  requireOpenRange(prefix + ".poisson_ratio", spec.poisson_ratio, -1.0, 0.5);
  requirePositive(prefix + ".density", spec.density);
  for (int i = 0; i < 3; ++i) requireFinite(prefix + ".offset", spec.offset[i]);
  try {
    mesh = readGmsh(spec.msh_path);
  } catch (const InputError& e) {
    throw e.as(prefix + ".mesh.msh_file");
  }
  material = {spec.youngs_modulus, spec.poisson_ratio, spec.density};
  for (Vec3& x : mesh.nodes) x += spec.offset;
  std::vector<std::array<std::uint32_t, 3>> triangles = surfaceTriangles(mesh);
  std::vector<std::uint32_t> newOf;
  renumber(mesh.nodes, triangles, newOf);
  for (auto& n : mesh.tets) n = newOf[n];
  mesh.faces.clear();
  const std::size_t npt = mesh.nodesPerTet();
  elements.reserve(mesh.tetCount());
  for (std::size_t e = 0; e < mesh.tetCount(); ++e) {
    elements.emplace_back(mesh.tets.begin() + static_cast<long>(e * npt),
                          mesh.tets.begin() + static_cast<long>((e + 1) * npt));
  }
  FemMatrices matrices = assembleTetMesh(mesh, material, spec.mass == FemMass::kLumped);
  k = std::move(matrices.stiffness);
  m = std::move(matrices.mass);
  assembled = true;
  constrain(spec, newOf, mesh.tags);
}

void FemBody::Impl::buildFromMatrices(const FemSpec& spec) {
  std::vector<Vec3> nodes;
  const auto readMatrix = [&](const std::string& path, const std::string& field) {
    try {
      return readMatrixMarket(path, 3 * nodes.size());
    } catch (const InputError& e) {
      throw e.as(prefix + "." + field);
    }
  };
  std::vector<std::array<std::uint32_t, 3>> triangles;
  try {
    nodes = readNodeFile(spec.nodes_path);
  } catch (const InputError& e) {
    throw e.as(prefix + ".matrices.nodes_file");
  }
  try {
    triangles = readTriangleFile(spec.triangles_path, nodes.size());
  } catch (const InputError& e) {
    throw e.as(prefix + ".matrices.triangles_file");
  }
  const auto dofs = static_cast<Eigen::Index>(3 * nodes.size());
  const auto check = [&](const SparseMatrix& a, const std::string& field) {
    if (a.rows() != dofs || a.cols() != dofs) {
      throw InputError(prefix + "." + field, std::to_string(a.rows()) + " x " + std::to_string(a.cols()),
                       "must be " + std::to_string(dofs) + " x " + std::to_string(dofs) +
                           " (3 DOF per node of the node file)");
    }
    const double norm = a.norm();
    const double asym = (a - SparseMatrix(a.transpose())).norm();
    if (!(asym <= 1e-9 * norm)) {
      throw InputError(prefix + "." + field, formatValue(asym / norm) + " relative asymmetry",
                       "must be symmetric");
    }
  };
  k = readMatrix(spec.stiffness_matrix_path, "matrices.stiffness_matrix_file");
  check(k, "matrices.stiffness_matrix_file");
  m = readMatrix(spec.mass_matrix_path, "matrices.mass_matrix_file");
  check(m, "matrices.mass_matrix_file");
  for (Eigen::Index i = 0; i < dofs; ++i) {
    if (!(m.coeff(i, i) > 0.0)) {
      throw InputError(prefix + ".matrices.mass_matrix_file", "DOF " + std::to_string(i + 1),
                       "diagonal entry must be > 0");
    }
  }
  if (!spec.damping_matrix_path.empty()) {
    c = readMatrix(spec.damping_matrix_path, "matrices.damping_matrix_file");
    check(c, "matrices.damping_matrix_file");
    explicitDamping = true;
  }
  for (Vec3& x : nodes) x += spec.offset;
  std::vector<std::uint32_t> newOf;
  renumber(nodes, triangles, newOf);
  k = permuted(k, newOf);
  m = permuted(m, newOf);
  if (explicitDamping) c = permuted(c, newOf);
  std::vector<std::uint64_t> ids(newOf.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = i;
  constrain(spec, newOf, ids);
}

void FemBody::Impl::constrain(const FemSpec& spec, const std::vector<std::uint32_t>& newOf,
                              const std::vector<std::uint64_t>& inputIds) {
  const std::size_t n = nodes();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> byId;  // input id -> body node
  byId.reserve(n);
  for (std::size_t i = 0; i < inputIds.size(); ++i) byId.emplace_back(inputIds[i], newOf[i]);
  std::sort(byId.begin(), byId.end());
  std::vector<Vec3> positions(n);
  for (std::size_t i = 0; i < n; ++i) positions[i] = at(x0, i);
  constraints = NodeConstraints(
      spec, positions,
      [&](std::uint32_t id) -> std::optional<std::uint32_t> {
        const auto it = std::lower_bound(byId.begin(), byId.end(), std::pair<std::uint64_t, std::uint32_t>{id, 0});
        if (it == byId.end() || it->first != id) return std::nullopt;
        return it->second;
      },
      "no such node (a Gmsh node tag of a tetrahedron, or a 0-based node-file index)", ConstraintOverlap::kFixedWins,
      prefix);
  freeIndex.assign(3 * n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t a = 0; a < 3; ++a) {
      const auto dof = static_cast<std::uint32_t>(3 * i) + a;
      const NodeRole role = constraints.role(i);
      if (role == NodeRole::kFree) {
        freeIndex[dof] = static_cast<std::int32_t>(freeDofs.size());
        freeDofs.push_back(dof);
      } else {
        (role == NodeRole::kFixed ? fixedDofs : drivenDofs).push_back(dof);
      }
    }
  }
  kFixed = selectRows(k, fixedDofs);
  mFixed = selectRows(m, fixedDofs);
  kDriven = selectRows(k, drivenDofs);
  mDriven = selectRows(m, drivenDofs);
  if (explicitDamping) {
    cFixed = selectRows(c, fixedDofs);
    cDriven = selectRows(c, drivenDofs);
  } else {
    cFixed = alpha * kFixed + beta * mFixed;
    cDriven = alpha * kDriven + beta * mDriven;
  }
  const VectorXd ex = VectorXd::NullaryExpr(3 * static_cast<Eigen::Index>(n),
                                            [](Eigen::Index i) { return i % 3 == 0 ? 1.0 : 0.0; });
  mass = ex.dot(m * ex);
  u = u1 = u2 = v = fc1 = fc0 = gravityLoad = VectorXd::Zero(3 * static_cast<Eigen::Index>(n));
}

void FemBody::Impl::factorise() {
  const std::size_t nf = freeDofs.size();
  if (integrator == FemIntegrator::kThreeLevel) {
    SparseMatrix a = m / (dt * dt) + k / 3.0;
    a += (explicitDamping ? c : SparseMatrix(alpha * k + beta * m)) / (2.0 * dt);
    if (nf == 0) return;  // everything prescribed: nothing to solve for
    a1.compute(block(a, freeIndex, nf));
    if (!positiveDefinite(a1, static_cast<Eigen::Index>(nf))) {
      throw InputError(prefix, "A1 = M/dt^2 + C/(2 dt) + K/3",
                       "is not positive definite on the free DOFs (check M, K and the damping)");
    }
    return;
  }
  // Central differences need a diagonal mass.
  for (int col = 0; col < m.outerSize(); ++col) {
    for (SparseMatrix::InnerIterator it(m, col); it; ++it) {
      if (it.row() != it.col() && it.value() != 0.0) {
        throw InputError(
            prefix + ".integrator", "central_difference",
            "needs a lumped (diagonal) mass matrix; use mass = lumped or the three-level scheme");
      }
    }
  }
  lumpedFree.resize(static_cast<Eigen::Index>(nf));
  for (std::size_t i = 0; i < nf; ++i)
    lumpedFree[static_cast<Eigen::Index>(i)] = m.coeff(freeDofs[i], freeDofs[i]);
  omegaMax = std::sqrt(std::max(0.0, largestEigenvalue(block(k, freeIndex, nf), lumpedFree)));
}

FemBody::FemBody(const FemSpec& spec, double timeStep, const std::string& fieldPrefix)
    : impl_(std::make_unique<Impl>()) {
  Impl& b = *impl_;
  b.name = spec.name;
  b.prefix = fieldPrefix;
  b.integrator = spec.integrator;
  requirePositive(fieldPrefix + ".time_step", timeStep);
  requireNonNegative(fieldPrefix + ".rayleigh_alpha", spec.rayleigh_alpha);
  requireNonNegative(fieldPrefix + ".rayleigh_beta", spec.rayleigh_beta);
  b.dt = timeStep;
  b.alpha = spec.rayleigh_alpha;
  b.beta = spec.rayleigh_beta;
  const bool fromMesh = !spec.msh_path.empty();
  const bool fromMatrices = !spec.mass_matrix_path.empty() || !spec.stiffness_matrix_path.empty();
  if (fromMesh == fromMatrices) {
    throw InputError(
        fieldPrefix + ".mesh.msh_file", fromMesh ? spec.msh_path : "(empty)",
        "give either a .msh mesh or the mass and stiffness matrices with node and triangle files");
  }
  if (fromMesh) {
    b.buildFromMesh(spec);
  } else {
    for (const auto& [path, field] :
         {std::pair{&spec.mass_matrix_path, "matrices.mass_matrix_file"},
          std::pair{&spec.stiffness_matrix_path, "matrices.stiffness_matrix_file"},
          std::pair{&spec.nodes_path, "matrices.nodes_file"},
          std::pair{&spec.triangles_path, "matrices.triangles_file"}}) {
      if (path->empty())
        throw InputError(fieldPrefix + "." + field, "(empty)", "needed for imported matrices");
    }
    b.buildFromMatrices(spec);
  }
  b.surface =
      DeformableSurface(b.surface.positions().size(), b.surface.triangles(), spec.material, fieldPrefix);
  b.factorise();
  b.writeSurface();
}

FemBody::~FemBody() = default;

// ---------------------------------------------------------------------------------------------
// Stepping

void FemBody::Impl::prescribe(VectorXd& target, VectorXd* velocity) const {
  for (const std::uint32_t node : constraints.fixed()) {
    target.segment<3>(3 * static_cast<Eigen::Index>(node)).setZero();
    if (velocity != nullptr) velocity->segment<3>(3 * static_cast<Eigen::Index>(node)).setZero();
  }
  constraints.forEachDriven([&](std::uint32_t node, const Vec3& position, const Vec3& nodeVelocity) {
    const auto s = 3 * static_cast<Eigen::Index>(node);
    target.segment<3>(s) = position - at(x0, node);
    if (velocity != nullptr) velocity->segment<3>(s) = nodeVelocity;
  });
}

void FemBody::Impl::updateGravity(const Vec3& g) {
  if (g == gravity) return;
  gravity = g;
  VectorXd rigid(x0.size());
  for (Eigen::Index i = 0; i < rigid.size(); ++i) rigid[i] = g[i % 3];
  gravityLoad = m * rigid;
}

VectorXd FemBody::Impl::contactLoad() const {
  VectorXd f = VectorXd::Zero(x0.size());
  const auto& forces = surface.nodeForces();
  for (std::size_t i = 0; i < forces.size(); ++i) f.segment<3>(3 * static_cast<Eigen::Index>(i)) = forces[i];
  return f;
}

void FemBody::Impl::writeSurface() {
  auto& positions = surface.positions();
  auto& velocities = surface.velocities();
  for (std::size_t i = 0; i < positions.size(); ++i) {
    positions[i] = at(x0, i) + at(u, i);
    velocities[i] = at(v, i);
  }
}

NodeReaction FemBody::Impl::reaction(const std::vector<std::uint32_t>& dofs, const VectorXd& r,
                                     const Vec3& about) const {
  NodeReaction out;
  for (std::size_t j = 0; j + 2 < dofs.size(); j += 3) {
    const std::size_t node = dofs[j] / 3;
    const Vec3 f = r.segment<3>(static_cast<Eigen::Index>(j));
    out.force += f;
    out.torque += (at(x0, node) + at(u1, node) - about).cross(f);
  }
  return out;
}

void FemBody::beginStep(double dt, const Vec3& gravity) {
  Impl& b = *impl_;
  if (dt != b.dt) {
    throw InputError(b.prefix + ".time_step", formatValue(dt),
                     "differs from the step the FEM body was built for (" + formatValue(b.dt) + " s)");
  }
  b.updateGravity(gravity);
  b.constraints.advance(dt);
  VectorXd next = VectorXd::Zero(b.u.size());
  b.prescribe(next, nullptr);
  VectorXd rhs;
  if (b.integrator == FemIntegrator::kThreeLevel) {
    // A3 U + A4 U- - A1 Up + (2 F + F-)/3, with Up the prescribed part of U+.
    rhs = b.combine((2.0 * b.u - b.u1 - next) / (dt * dt), (b.u + b.u1 + next) / 3.0,
                    (b.u1 - next) / (2.0 * dt)) +
          b.gravityLoad + (2.0 * b.fc1 + b.fc0) / 3.0;
    VectorXd rf(static_cast<Eigen::Index>(b.freeDofs.size()));
    for (std::size_t i = 0; i < b.freeDofs.size(); ++i) rf[static_cast<Eigen::Index>(i)] = rhs[b.freeDofs[i]];
    const VectorXd xf = rf.size() > 0 ? VectorXd(b.a1.solve(rf)) : rf;
    for (std::size_t i = 0; i < b.freeDofs.size(); ++i)
      next[b.freeDofs[i]] = xf[static_cast<Eigen::Index>(i)];
  } else {
    rhs = b.gravityLoad + b.fc1 + b.combine(VectorXd::Zero(b.u.size()), b.u, (b.u1 - b.u) / dt);
    for (std::size_t i = 0; i < b.freeDofs.size(); ++i) {
      const std::uint32_t d = b.freeDofs[i];
      next[d] = 2.0 * b.u[d] - b.u1[d] + dt * dt * rhs[d] / b.lumpedFree[static_cast<Eigen::Index>(i)];
    }
  }
  b.u2 = std::move(b.u1);
  b.u1 = std::move(b.u);
  b.u = std::move(next);
  b.v = (3.0 * b.u - 4.0 * b.u1 + b.u2) / (2.0 * dt);
  b.prescribe(b.u, &b.v);
  b.writeSurface();
}

void FemBody::endStep(double dt, const Vec3& gravity) {
  Impl& b = *impl_;
  b.updateGravity(gravity);
  const VectorXd fc = b.contactLoad();
  // Residual on the prescribed rows at the middle level U (= u1 here): what the constraint applies.
  const auto residual = [&](const SparseMatrix& kp, const SparseMatrix& mp, const SparseMatrix& cp,
                            const std::vector<std::uint32_t>& dofs) {
    VectorXd r;
    if (b.integrator == FemIntegrator::kThreeLevel) {
      r = mp * ((b.u - 2.0 * b.u1 + b.u2) / (dt * dt)) + cp * ((b.u - b.u2) / (2.0 * dt)) +
          kp * ((b.u + b.u1 + b.u2) / 3.0);
      for (std::size_t j = 0; j < dofs.size(); ++j) {
        r[static_cast<Eigen::Index>(j)] -=
            b.gravityLoad[dofs[j]] + (fc[dofs[j]] + b.fc1[dofs[j]] + b.fc0[dofs[j]]) / 3.0;
      }
    } else {
      r = mp * ((b.u - 2.0 * b.u1 + b.u2) / (dt * dt)) + cp * ((b.u1 - b.u2) / dt) + kp * b.u1;
      for (std::size_t j = 0; j < dofs.size(); ++j)
        r[static_cast<Eigen::Index>(j)] -= b.gravityLoad[dofs[j]] + b.fc1[dofs[j]];
    }
    return r;
  };
  b.constraints.setReactions(
      b.reaction(b.fixedDofs, residual(b.kFixed, b.mFixed, b.cFixed, b.fixedDofs), Vec3::Zero()),
      b.reaction(b.drivenDofs, residual(b.kDriven, b.mDriven, b.cDriven, b.drivenDofs),
                 b.constraints.pose().position));
  b.fc0 = std::move(b.fc1);
  b.fc1 = fc;
}

void FemBody::solveStatic(const Vec3& gravity) {
  Impl& b = *impl_;
  if (b.fixedDofs.empty() && b.drivenDofs.empty()) {
    throw InputError(b.prefix, "no fixed or driven nodes", "a static solution needs constrained nodes");
  }
  b.updateGravity(gravity);
  const VectorXd fc = b.contactLoad();
  VectorXd u = VectorXd::Zero(b.u.size());
  b.prescribe(u, nullptr);
  const VectorXd rhs = b.gravityLoad + fc - b.k * u;
  VectorXd rf(static_cast<Eigen::Index>(b.freeDofs.size()));
  for (std::size_t i = 0; i < b.freeDofs.size(); ++i) rf[static_cast<Eigen::Index>(i)] = rhs[b.freeDofs[i]];
  Factorisation kff;
  if (rf.size() > 0) kff.compute(block(b.k, b.freeIndex, b.freeDofs.size()));
  if (rf.size() > 0 && kff.info() != Eigen::Success) {
    throw InputError(b.prefix, "K", "cannot be factorised on the free DOFs");
  }
  const VectorXd xf = rf.size() > 0 ? VectorXd(kff.solve(rf)) : rf;
  for (std::size_t i = 0; i < b.freeDofs.size(); ++i) u[b.freeDofs[i]] = xf[static_cast<Eigen::Index>(i)];
  b.u = b.u1 = b.u2 = u;
  b.v.setZero();
  b.prescribe(b.u, &b.v);
  b.fc1 = b.fc0 = fc;
  const auto reactionRows = [&](const SparseMatrix& kp, const std::vector<std::uint32_t>& dofs) {
    VectorXd r = kp * u;
    for (std::size_t j = 0; j < dofs.size(); ++j)
      r[static_cast<Eigen::Index>(j)] -= b.gravityLoad[dofs[j]] + fc[dofs[j]];
    return r;
  };
  b.constraints.setReactions(b.reaction(b.fixedDofs, reactionRows(b.kFixed, b.fixedDofs), Vec3::Zero()),
                             b.reaction(b.drivenDofs, reactionRows(b.kDriven, b.drivenDofs),
                                        b.constraints.pose().position));
  b.writeSurface();
}

// ---------------------------------------------------------------------------------------------
// Queries

const std::string& FemBody::name() const { return impl_->name; }
DeformableSurface& FemBody::surface() { return impl_->surface; }
const DeformableSurface& FemBody::surface() const { return impl_->surface; }

double FemBody::criticalTimeStep() const {
  const Impl& b = *impl_;
  if (b.integrator == FemIntegrator::kThreeLevel || b.omegaMax <= 0.0)
    return std::numeric_limits<double>::infinity();
  const double w2 = b.omegaMax * b.omegaMax;
  const double d = b.beta + b.alpha * w2;  // dt solves w2 dt^2 + 2 d dt - 4 = 0
  return (std::sqrt(d * d + 4.0 * w2) - d) / w2;
}

std::string FemBody::criticalTimeStepReason() const {
  const Impl& b = *impl_;
  if (b.integrator == FemIntegrator::kThreeLevel) return "FEM three-level scheme: unconditionally stable";
  return "FEM central differences: omega_max = " + formatValue(b.omegaMax) +
         " rad/s (Lanczos on the free DOFs), dt < 2/omega_max reduced by the Rayleigh damping";
}

void FemBody::setDrivenPose(const Vec3& position, const Quat& orientation, const Vec3& linearVelocity,
                            const Vec3& angularVelocity) {
  impl_->constraints.setPose({position, orientation, linearVelocity, angularVelocity}, impl_->prefix);
}

bool FemBody::hasDrivenNodes() const { return !impl_->drivenDofs.empty(); }
NodeReaction FemBody::drivenReaction() const { return impl_->constraints.drivenReaction(); }
NodeReaction FemBody::fixedReaction() const { return impl_->constraints.fixedReaction(); }
std::size_t FemBody::nodeCount() const { return impl_->nodes(); }
Vec3 FemBody::nodePosition(std::size_t node) const {
  return impl_->at(impl_->x0, node) + impl_->at(impl_->u, node);
}
Vec3 FemBody::nodeDisplacement(std::size_t node) const { return impl_->at(impl_->u, node); }
Vec3 FemBody::nodeVelocity(std::size_t node) const { return impl_->at(impl_->v, node); }
double FemBody::kineticEnergy() const { return 0.5 * impl_->v.dot(impl_->m * impl_->v); }
double FemBody::strainEnergy() const { return 0.5 * impl_->u.dot(impl_->k * impl_->u); }
double FemBody::totalMass() const { return impl_->mass; }
const Eigen::SparseMatrix<double>& FemBody::massMatrix() const { return impl_->m; }
const Eigen::SparseMatrix<double>& FemBody::stiffnessMatrix() const { return impl_->k; }
const std::vector<std::vector<std::uint32_t>>& FemBody::elements() const { return impl_->elements; }

std::vector<double> FemBody::vonMisesStress() const {
  if (!impl_->assembled) return {};
  return vonMisesAtCentroids(impl_->mesh, impl_->material, impl_->u);
}

// ---------------------------------------------------------------------------------------------
// Checkpoint

void FemBody::save(StateWriter& out) const {
  const Impl& b = *impl_;
  out.writeString(b.name);
  out.write<std::uint64_t>(static_cast<std::uint64_t>(b.u.size()));
  out.write<std::uint8_t>(static_cast<std::uint8_t>(b.integrator));
  out.write(b.dt);
  for (const VectorXd* vec : {&b.u, &b.u1, &b.u2, &b.v, &b.fc1, &b.fc0}) out.writeVector(toStd(*vec));
  b.constraints.save(out);
}

void FemBody::restore(StateReader& in) {
  Impl& b = *impl_;
  const std::string name = in.readString();
  requireEqual(in, "FEM body name \"" + name + "\"", name, b.name);
  const auto dofs = in.read<std::uint64_t>();
  requireEqual(in, "DOF count " + std::to_string(dofs) + " of FEM body \"" + name + "\"", dofs,
               static_cast<std::uint64_t>(b.u.size()));
  const auto integrator = in.read<std::uint8_t>();
  requireEqual(in, "integrator of FEM body \"" + name + "\"", integrator,
               static_cast<std::uint8_t>(b.integrator));
  const auto dt = in.read<double>();
  requireEqual(in, "time step of FEM body \"" + name + "\"", dt, b.dt);
  std::array<VectorXd, 6> vecs;
  for (VectorXd& vec : vecs) vec = fromStd(in, in.readVector<double>(), b.u.size(), "FEM state vector");
  b.constraints.restore(in);
  b.u = std::move(vecs[0]);
  b.u1 = std::move(vecs[1]);
  b.u2 = std::move(vecs[2]);
  b.v = std::move(vecs[3]);
  b.fc1 = std::move(vecs[4]);
  b.fc0 = std::move(vecs[5]);
  b.writeSurface();
}

}  // namespace demlink::core
