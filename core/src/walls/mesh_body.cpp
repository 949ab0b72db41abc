/// Rigid, kinematically driven triangle mesh; see mesh_body.hpp for the kinematics.
///
/// Normals are computed once in the body frame and rotated with the body (a rotation
/// preserves unit length and the right-hand orientation of (b-a)x(c-a)), which is cheaper
/// and more accurate than re-deriving them from the world vertices every step.
/// The rotation update composes quaternions and re-normalises, so the orientation stays a
/// unit quaternion over arbitrarily many steps.
#include "demlink/core/walls/mesh_body.hpp"

#include <algorithm>
#include <cmath>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/unit_quaternion.hpp"
#include "demlink/core/state/state_stream.hpp"
#include "demlink/core/geometry/stl_reader.hpp"

namespace demlink::core {
namespace {

std::string formatVec(const Vec3& v) {
  return "(" + formatValue(v.x()) + ", " + formatValue(v.y()) + ", " + formatValue(v.z()) + ")";
}

void requireFiniteVec(const std::string& field, const Vec3& v) {
  if (!v.allFinite()) throw InputError(field, formatVec(v), "all components must be finite");
}

}  // namespace

TriangleMesh axisAlignedBoxMesh(const Vec3& lo, const Vec3& hi) {
  requireFiniteVec("box.lo", lo);
  requireFiniteVec("box.hi", hi);
  if (!(hi.array() > lo.array()).all()) {
    throw InputError("box.hi", formatVec(hi),
                     "must exceed box.lo " + formatVec(lo) + " in every component");
  }
  TriangleMesh mesh;
  // Corner k has x = hi.x if bit 0 of k is set, y = hi.y if bit 1, z = hi.z if bit 2.
  for (std::uint32_t k = 0; k < 8; ++k) {
    mesh.vertices.emplace_back((k & 1u) != 0 ? hi.x() : lo.x(), (k & 2u) != 0 ? hi.y() : lo.y(),
                               (k & 4u) != 0 ? hi.z() : lo.z());
  }
  // Two counter-clockwise (seen from outside) triangles per face.
  mesh.triangles = {{0, 2, 1}, {1, 2, 3},   // z = lo, normal -z
                    {4, 5, 7}, {4, 7, 6},   // z = hi, normal +z
                    {0, 1, 5}, {0, 5, 4},   // y = lo, normal -y
                    {2, 6, 7}, {2, 7, 3},   // y = hi, normal +y
                    {0, 4, 6}, {0, 6, 2},   // x = lo, normal -x
                    {1, 3, 7}, {1, 7, 5}};  // x = hi, normal +x
  return mesh;
}

TriangleMesh rectangleMesh(const Vec3& centre, double halfX, double halfY, std::uint32_t nx,
                           std::uint32_t ny) {
  requireFiniteVec("rectangle.centre", centre);
  requirePositive("rectangle.half_x", halfX);
  requirePositive("rectangle.half_y", halfY);
  if (nx < 1) throw InputError("rectangle.nx", std::to_string(nx), "must be >= 1");
  if (ny < 1) throw InputError("rectangle.ny", std::to_string(ny), "must be >= 1");
  TriangleMesh mesh;
  mesh.vertices.reserve(std::size_t{nx + 1} * (ny + 1));
  for (std::uint32_t j = 0; j <= ny; ++j) {
    for (std::uint32_t i = 0; i <= nx; ++i) {
      const double fx = 2.0 * static_cast<double>(i) / static_cast<double>(nx) - 1.0;
      const double fy = 2.0 * static_cast<double>(j) / static_cast<double>(ny) - 1.0;
      mesh.vertices.emplace_back(centre.x() + halfX * fx, centre.y() + halfY * fy, centre.z());
    }
  }
  const auto id = [nx](std::uint32_t i, std::uint32_t j) { return j * (nx + 1) + i; };
  for (std::uint32_t j = 0; j < ny; ++j) {
    for (std::uint32_t i = 0; i < nx; ++i) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return mesh;
}

MeshBody::MeshBody(std::string name, std::vector<Vec3> localVertices,
                   std::vector<std::array<std::uint32_t, 3>> triangles, std::uint32_t materialIndex)
    : name_(std::move(name)),
      local_vertices_(std::move(localVertices)),
      triangles_(std::move(triangles)),
      material_index_(materialIndex) {
  const std::string prefix = name_.empty() ? std::string("mesh") : name_;
  if (triangles_.empty()) throw InputError(prefix + ".triangles", "0", "mesh has no triangles");
  for (std::size_t i = 0; i < local_vertices_.size(); ++i) {
    requireFiniteVec(prefix + ".vertices[" + std::to_string(i) + "]", local_vertices_[i]);
    bounding_radius_ = std::max(bounding_radius_, local_vertices_[i].norm());
  }
  local_normals_.reserve(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    for (const std::uint32_t idx : triangles_[t]) {
      if (idx >= local_vertices_.size()) {
        throw InputError(
            prefix + ".triangles[" + std::to_string(t) + "]", std::to_string(idx),
            "vertex index out of range (" + std::to_string(local_vertices_.size()) + " vertices)");
      }
    }
    const auto& tri = triangles_[t];
    const Vec3 n = (local_vertices_[tri[1]] - local_vertices_[tri[0]])
                       .cross(local_vertices_[tri[2]] - local_vertices_[tri[0]]);
    const double len = n.norm();
    local_normals_.push_back(len > 0.0 ? Vec3(n / len) : Vec3::Zero());
  }
  updateWorldGeometry();
  markNeighbourBuild();
}

MeshBody MeshBody::fromStl(std::string name, const std::string& path,
                           const Vec3& referencePointInFile, std::uint32_t materialIndex) {
  requireFiniteVec("reference_point", referencePointInFile);
  StlMesh stl = readStl(path);
  for (Vec3& v : stl.vertices) v -= referencePointInFile;
  MeshBody body(std::move(name), std::move(stl.vertices), std::move(stl.triangles), materialIndex);
  body.load_warnings_ = std::move(stl.warnings);
  body.setPose(referencePointInFile, Quat::Identity());
  body.markNeighbourBuild();
  return body;
}

void MeshBody::setPose(const Vec3& position, const Quat& orientation) {
  requireFiniteVec("pose.position", position);
  const double norm = quaternionNorm(orientation);
  if (!orientation.coeffs().allFinite() || !(norm > 1e-12)) {
    const auto& q = orientation;
    throw InputError("pose.orientation",
                     "(w=" + formatValue(q.w()) + ", x=" + formatValue(q.x()) +
                         ", y=" + formatValue(q.y()) + ", z=" + formatValue(q.z()) + ")",
                     "quaternion must be finite with non-zero norm");
  }
  state_.position = position;
  state_.orientation = Quat(orientation.coeffs() / norm);
  updateWorldGeometry();
}

void MeshBody::setVelocity(const Vec3& linear, const Vec3& angular) {
  requireFiniteVec("velocity.linear", linear);
  requireFiniteVec("velocity.angular", angular);
  state_.linear_velocity = linear;
  state_.angular_velocity = angular;
}

void MeshBody::advance(double dt) {
  requireFinite("dt", dt);
  state_.position += state_.linear_velocity * dt;
  const double rate = state_.angular_velocity.norm();
  const double angle = rate * dt;
  if (angle != 0.0) {
    const Vec3 axisSin = std::sin(0.5 * angle) * (state_.angular_velocity / rate);
    const Quat dq(std::cos(0.5 * angle), axisSin.x(), axisSin.y(), axisSin.z());
    state_.orientation = (dq * state_.orientation).normalized();
  }
  updateWorldGeometry();
}

void MeshBody::updateWorldGeometry() {
  const Mat3 rot = state_.orientation.toRotationMatrix();
  world_vertices_.resize(local_vertices_.size());
  for (std::size_t i = 0; i < local_vertices_.size(); ++i) {
    world_vertices_[i] = state_.position + rot * local_vertices_[i];
  }
  world_normals_.resize(local_normals_.size());
  for (std::size_t t = 0; t < local_normals_.size(); ++t) world_normals_[t] = rot * local_normals_[t];
}

Vec3 MeshBody::velocityAt(const Vec3& worldPoint) const {
  return state_.linear_velocity + state_.angular_velocity.cross(worldPoint - state_.position);
}

void MeshBody::addContactForce(const Vec3& forceOnMesh, const Vec3& worldPoint) {
  state_.force += forceOnMesh;
  state_.torque += (worldPoint - state_.position).cross(forceOnMesh);
}

void MeshBody::addWrench(const Vec3& force, const Vec3& torqueAboutReference) {
  state_.force += force;
  state_.torque += torqueAboutReference;
}

void MeshBody::clearWrench() {
  state_.force.setZero();
  state_.torque.setZero();
}

void MeshBody::setCollisionWindow(double from, double until) {
  if (std::isnan(from)) throw InputError("active_from", formatValue(from), "must be a number");
  if (std::isnan(until)) throw InputError("active_until", formatValue(until), "must be a number");
  if (until < from) {
    throw InputError("active_until", formatValue(until), "must not be earlier than active_from = " + formatValue(from));
  }
  collide_from_ = from;
  collide_until_ = until;
}

void MeshBody::markNeighbourBuild() {
  state_.mark_position = state_.position;
  state_.mark_orientation = state_.orientation;
}

double MeshBody::maxDisplacementSinceMark() const {
  // Relative rotation q q0^-1 has |vec| = sin(theta/2) (for a unit quaternion).
  const Quat rel = state_.orientation * state_.mark_orientation.conjugate();
  const double relNorm = rel.norm();
  const double sinHalf = relNorm > 0.0 ? std::min(1.0, rel.vec().norm() / relNorm) : 0.0;
  return (state_.position - state_.mark_position).norm() + 2.0 * bounding_radius_ * sinHalf;
}

void MeshBody::save(StateWriter& out) const {
  out.writeString(name_);
  out.write<std::uint64_t>(triangles_.size());
  out.write(state_.position);
  out.write(state_.orientation);
  out.write(state_.linear_velocity);
  out.write(state_.angular_velocity);
  out.write(state_.force);
  out.write(state_.torque);
  out.write(state_.mark_position);
  out.write(state_.mark_orientation);
}

MeshBody::State MeshBody::readState(StateReader& in) const {
  const std::string name = in.readString();
  requireEqual(in, "mesh name \"" + name + "\"", name, name_);
  const auto triangles = in.read<std::uint64_t>();
  requireEqual(in, "triangle count " + std::to_string(triangles) + " of mesh \"" + name + "\"", triangles,
               static_cast<std::uint64_t>(triangles_.size()));
  State state;
  state.position = in.read<Vec3>();
  state.orientation = in.read<Quat>();
  state.linear_velocity = in.read<Vec3>();
  state.angular_velocity = in.read<Vec3>();
  state.force = in.read<Vec3>();
  state.torque = in.read<Vec3>();
  state.mark_position = in.read<Vec3>();
  state.mark_orientation = in.read<Quat>();
  if (!(std::abs(state.orientation.norm() - 1.0) < 1.0e-9)) in.fail("orientation", "not a unit quaternion");
  return state;
}

void MeshBody::restoreState(const State& state) {
  state_ = state;
  updateWorldGeometry();
}

void MeshBody::setSpeedLimit(double speed) {
  requireNonNegative("max_speed", speed);
  requireFinite("max_speed", speed);
  speed_limit_ = speed;
}

}  // namespace demlink::core
