/// Facet bodies (facets.proto, translate_facets.cpp) and the bounds and frame settings
/// of a SimulationBox (translate_frame.cpp): geometry sources agree with each other,
/// roles and collision windows act as declared, bad input names its field.
#include <gtest/gtest.h>

#include <cmath>

#include "demlink/core/base/input_error.hpp"
#include "demlink/core/walls/mesh_body.hpp"
#include "demlink/core/geometry/stl_reader.hpp"
#include "demlink/server/scene/scene_translator.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

void setVec(v1::Vector3* out, double x, double y, double z) {
  out->set_x(x);
  out->set_y(y);
  out->set_z(z);
}

/// A scene with a simulation box (dt 1e-5 s, gravity g), a material "steel" and
/// one sphere of radius 4 mm at `position` moving at `velocity`.
v1::Scene baseScene(const core::Vec3& gravity, const core::Vec3& position, const core::Vec3& velocity) {
  v1::Scene scene;
  auto* box = scene.add_components();
  box->set_name("box");
  box->mutable_simulation_box()->set_time_step(1.0e-5);
  box->mutable_simulation_box()->set_end_time(1.0);
  setVec(box->mutable_simulation_box()->mutable_gravity(), gravity.x(), gravity.y(), gravity.z());
  auto* steel = scene.add_components();
  steel->set_name("steel");
  steel->mutable_material()->set_sliding_friction(0.4);
  auto* sphere = scene.add_components();
  sphere->set_name("sphere");
  v1::ParticleLattice* lattice = sphere->mutable_particle_lattice();
  lattice->set_material("steel");
  lattice->set_radius(0.004);
  lattice->set_spacing(0.01);
  setVec(lattice->mutable_origin(), position.x(), position.y(), position.z());
  setVec(lattice->mutable_velocity(), velocity.x(), velocity.y(), velocity.z());
  lattice->mutable_counts()->set_nx(1);
  lattice->mutable_counts()->set_ny(1);
  lattice->mutable_counts()->set_nz(1);
  return scene;
}

v1::FacetBody* addFacet(v1::Scene& scene, const std::string& name) {
  auto* component = scene.add_components();
  component->set_name(name);
  component->mutable_facet_body()->set_material("steel");
  return component->mutable_facet_body();
}

/// Appends the triangles of `mesh` to a facet triangle list.
void setTriangles(v1::FacetBody* facet, const core::TriangleMesh& mesh) {
  for (const auto& t : mesh.triangles) {
    v1::FacetTriangle* tri = facet->mutable_triangles()->add_triangles();
    v1::Vector3* corners[3] = {tri->mutable_a(), tri->mutable_b(), tri->mutable_c()};
    for (int k = 0; k < 3; ++k) {
      const core::Vec3& v = mesh.vertices[t[k]];
      setVec(corners[k], v.x(), v.y(), v.z());
    }
  }
}

core::InputError translationError(const v1::Scene& scene, const std::filesystem::path& dir = {}) {
  try {
    (void)translateScene(scene, dir);
  } catch (const core::InputError& error) {
    return error;
  }
  ADD_FAILURE() << "expected an InputError";
  return core::InputError("(none)", "", "");
}

/// A 0.1 m square floor at z = 0 of 2 x 2 cells, tilted a little so the sphere slides.
core::TriangleMesh floorMesh() {
  core::TriangleMesh mesh = core::rectangleMesh(core::Vec3::Zero(), 0.05, 0.05, 2, 2);
  for (core::Vec3& v : mesh.vertices) v.z() = 0.1 * v.x();
  return mesh;
}

TEST(FacetBody, TriangleListEqualsTheSameGeometryFromStl) {
  test::ScratchDir dir;
  const core::TriangleMesh mesh = floorMesh();
  core::writeStlAscii((dir.path() / "floor.stl").string(), mesh.vertices, mesh.triangles);
  const core::Vec3 start(-0.02, 0.003, 0.0045);
  const core::Vec3 velocity(0.3, 0.1, -0.2);
  v1::Scene fromStl = baseScene(core::Vec3(0.0, 0.0, -9.81), start, velocity);
  addFacet(fromStl, "floor")->set_stl_file("floor.stl");
  v1::Scene fromList = baseScene(core::Vec3(0.0, 0.0, -9.81), start, velocity);
  setTriangles(addFacet(fromList, "floor"), mesh);
  TranslatedScene a = translateScene(fromStl, dir.path());
  TranslatedScene b = translateScene(fromList, dir.path());
  ASSERT_EQ(a.world.meshes()[0].localVertices().size(), b.world.meshes()[0].localVertices().size());
  double maxForce = 0.0;
  double maxDifference = 0.0;
  for (int n = 0; n < 10000; ++n) {  // 0.1 s: impact, sliding across the cell edges
    a.world.step();
    b.world.step();
    maxForce = std::max(maxForce, a.world.meshes()[0].force().norm());
    maxDifference = std::max({maxDifference, (a.world.meshes()[0].force() - b.world.meshes()[0].force()).norm(),
                              (a.world.particles().force[0] - b.world.particles().force[0]).norm(),
                              (a.world.particles().position[0] - b.world.particles().position[0]).norm()});
  }
  EXPECT_GT(maxForce, 0.01);  // the sphere did touch the floor [N]
  EXPECT_LT(maxDifference, 1.0e-12);
}

/// A sphere flying at 1 m/s along x through a 4 cm box centred on its path, no gravity.
TranslatedScene flightThroughBox(v1::FacetBody::Role role) {
  v1::Scene scene = baseScene(core::Vec3::Zero(), core::Vec3(-0.05, 0.0, 0.0), core::Vec3(1.0, 0.0, 0.0));
  v1::FacetBody* box = addFacet(scene, "region");
  box->set_role(role);
  setVec(box->mutable_box()->mutable_size(), 0.04, 0.04, 0.04);
  TranslatedScene t = translateScene(scene, {});
  for (int n = 0; n < 10000; ++n) t.world.step();  // 0.1 s: from x = -0.05 to 0.05
  return t;
}

TEST(FacetBody, NonCollidingBodyDoesNotTouchAParticleThatPassesThrough) {
  const TranslatedScene passes = flightThroughBox(v1::FacetBody::NON_COLLIDING);
  EXPECT_EQ(passes.world.particles().velocity[0], core::Vec3(1.0, 0.0, 0.0));
  EXPECT_NEAR(passes.world.particles().position[0].x(), 0.05, 1.0e-12);
  EXPECT_EQ(passes.world.meshes()[0].force(), core::Vec3::Zero());
  // The same box as a wall stops it (so the flight above did cross the box).
  const TranslatedScene stopped = flightThroughBox(v1::FacetBody::FIXED);
  EXPECT_LT(stopped.world.particles().velocity[0].x(), 0.0);
}

TEST(FacetBody, GateThatStopsCollidingLetsARestingParticleFall) {
  constexpr double kOpen = 0.05;  // [s]
  constexpr double kG = 9.81;     // [m/s^2]
  v1::Scene scene = baseScene(core::Vec3(0.0, 0.0, -kG), core::Vec3(0.0, 0.0, 0.004), core::Vec3::Zero());
  v1::FacetBody* gate = addFacet(scene, "gate");
  setTriangles(gate, core::rectangleMesh(core::Vec3::Zero(), 0.02, 0.02, 1, 1));
  gate->set_active_until(kOpen);
  TranslatedScene t = translateScene(scene, {});
  for (int n = 0; n < 4000; ++n) t.world.step();  // t = 0.04: resting on the gate
  const double zRest = t.world.particles().position[0].z();
  EXPECT_NEAR(zRest, 0.004, 2.0e-5);
  EXPECT_LT(std::abs(t.world.particles().velocity[0].z()), 1.0e-3);
  for (int n = 0; n < 11000; ++n) t.world.step();  // t = 0.15: 0.1 s of free fall
  const double fall = 0.5 * kG * (t.world.time() - kOpen) * (t.world.time() - kOpen);
  EXPECT_NEAR(t.world.particles().position[0].z(), zRest - fall, 1.0e-4);
  EXPECT_NEAR(t.world.particles().velocity[0].z(), -kG * (t.world.time() - kOpen), 1.0e-3);
}

TEST(FacetBody, MovingBoxAdvancesAndOpenTopDropsOneFace) {
  v1::Scene scene = baseScene(core::Vec3::Zero(), core::Vec3(0.5, 0.5, 0.5), core::Vec3::Zero());
  v1::FacetBody* bin = addFacet(scene, "bin");
  bin->set_role(v1::FacetBody::MOVING);
  setVec(bin->mutable_box()->mutable_centre(), 0.1, 0.0, 0.0);
  setVec(bin->mutable_box()->mutable_size(), 0.2, 0.1, 0.05);
  bin->mutable_box()->set_open_top(true);
  setVec(bin->mutable_linear_velocity(), 0.0, 0.2, 0.0);
  TranslatedScene t = translateScene(scene, {});
  ASSERT_EQ(t.world.meshes()[0].triangles().size(), 10u);
  for (const core::Vec3& n : t.world.meshes()[0].triangleNormals()) EXPECT_LT(n.z(), 0.5);  // no +z face
  for (int n = 0; n < 1000; ++n) t.world.step();
  EXPECT_NEAR(t.world.meshes()[0].position().y(), 0.2 * t.world.time(), 1.0e-12);
}

TEST(FacetBody, BadInputNamesTheField) {
  const auto scene = [] { return baseScene(core::Vec3::Zero(), core::Vec3::Zero(), core::Vec3::Zero()); };
  const std::string at = "components[3].facet_body";
  {
    v1::Scene s = scene();
    core::TriangleMesh mesh = core::rectangleMesh(core::Vec3::Zero(), 0.02, 0.02, 1, 1);
    mesh.vertices[3] = mesh.vertices[1];  // triangle 0 (corners 0, 1, 3) collapses to a segment
    setTriangles(addFacet(s, "f"), mesh);
    EXPECT_EQ(translationError(s).field(), at + ".triangles.triangles[0]");
  }
  {
    v1::Scene s = scene();
    setVec(addFacet(s, "f")->mutable_box()->mutable_size(), 0.1, 0.0, 0.1);
    EXPECT_EQ(translationError(s).field(), at + ".box.size[1]");
  }
  {
    v1::Scene s = scene();
    v1::FacetBody* f = addFacet(s, "f");
    setVec(f->mutable_box()->mutable_size(), 0.1, 0.1, 0.1);
    f->set_role(static_cast<v1::FacetBody::Role>(7));
    EXPECT_EQ(translationError(s).field(), at + ".role");
  }
  {
    v1::Scene s = scene();
    v1::FacetBody* f = addFacet(s, "f");
    setVec(f->mutable_box()->mutable_size(), 0.1, 0.1, 0.1);
    f->set_active_from(0.2);
    f->set_active_until(0.1);
    EXPECT_EQ(translationError(s).field(), at + ".active_until");
  }
  {
    v1::Scene s = scene();
    addFacet(s, "f");
    EXPECT_EQ(translationError(s).field(), at);  // no geometry
  }
  {
    v1::Scene s = scene();
    v1::FacetBody* f = addFacet(s, "f");
    setVec(f->mutable_box()->mutable_size(), 0.1, 0.1, 0.1);
    setVec(f->mutable_linear_velocity(), 1.0, 0.0, 0.0);
    EXPECT_EQ(translationError(s).field(), at + ".linear_velocity");  // FIXED does not move
  }
  {
    v1::Scene s = scene();
    v1::FacetBody* f = addFacet(s, "f");
    f->set_stl_file("missing.stl");
    EXPECT_EQ(translationError(s).field(), at + ".stl_file");
  }
}

TEST(FrameSettings, GrowingBoundsAndFrameAreTranslated) {
  v1::Scene s = baseScene(core::Vec3::Zero(), core::Vec3::Zero(), core::Vec3::Zero());
  v1::SimulationBox* box = s.mutable_components(0)->mutable_simulation_box();
  setVec(box->mutable_bounds()->mutable_lower(), -1.0, -1.0, -1.0);
  setVec(box->mutable_bounds()->mutable_upper(), 1.0, 1.0, 1.0);
  box->mutable_bounds()->set_mode(v1::SimulationBox::Bounds::GROWING);
  setVec(box->mutable_bounds()->mutable_limit_lower(), -2.0, -2.0, -1.0);
  setVec(box->mutable_bounds()->mutable_limit_upper(), 2.0, 3.0, 4.0);
  setVec(box->mutable_frame()->mutable_linear_acceleration(), 1.0, 0.0, 0.0);
  setVec(box->mutable_frame()->mutable_angular_velocity(), 0.0, 0.0, 0.5);
  const TranslatedScene t = translateScene(s, {});
  ASSERT_TRUE(t.world.settings().bounds);
  EXPECT_TRUE(t.world.settings().bounds->growing);
  EXPECT_EQ(t.world.settings().bounds->limit_upper, core::Vec3(2.0, 3.0, 4.0));
  EXPECT_EQ(t.world.frameMotion().angular_velocity, core::Vec3(0.0, 0.0, 0.5));
  EXPECT_EQ(t.world.frameMotion().linear_acceleration, core::Vec3(1.0, 0.0, 0.0));

  box->mutable_bounds()->clear_limit_upper();
  EXPECT_EQ(translationError(s).field(), "components[0].simulation_box.bounds.limit_upper");
  setVec(box->mutable_bounds()->mutable_limit_upper(), 2.0, 3.0, 0.5);
  EXPECT_EQ(translationError(s).field(), "components[0].simulation_box.bounds.limit_upper[2]");
  setVec(box->mutable_bounds()->mutable_limit_upper(), 2.0, 3.0, 4.0);
  setVec(box->mutable_frame()->mutable_angular_velocity(), 0.0, NAN, 0.0);
  EXPECT_EQ(translationError(s).field(), "components[0].simulation_box.frame.angular_velocity[1]");
}

}  // namespace
}  // namespace demlink::server
