/// VTK XML output: the .vtp files carry the right arrays and values (read back
/// from both encodings), the .pvd indexes every frame, meshes are written as polys.
#include <gtest/gtest.h>

#include <cstring>
#include <sstream>

#include "demlink/core/output/vtk_writer.hpp"
#include "demlink/core/world.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

core::World smallWorld() {
  core::World world{core::SimulationSettings{}};
  core::Material glass;
  glass.name = "glass";
  world.addMaterial(glass);
  core::Material steel;
  steel.name = "steel";
  world.addMaterial(steel);
  world.addParticle({core::Vec3(0.125, 0.25, 0.5), core::Vec3(1, 2, 3), core::Vec3(0, 0, 9), 0.01, 0});
  world.addParticle({core::Vec3(-1.0 / 3.0, 0.0, 1e-7), core::Vec3::Zero(), core::Vec3::Zero(), 0.02, 1});
  world.addParticle({core::Vec3(0.75, 1.5, 2.25), core::Vec3(-4, 0, 0), core::Vec3::Zero(), 0.015, 1});
  return world;
}

const std::vector<std::string> kParticleArrays = {"position", "id", "radius", "velocity", "angular_velocity",
                                                  "force", "material", "clump_id", "connectivity", "offsets"};

/// The attribute `name` of the <DataArray Name="array"> element.
std::string arrayAttribute(const std::string& xml, const std::string& array, const std::string& name) {
  const std::size_t element = xml.rfind("<DataArray", xml.find("Name=\"" + array + "\""));
  const std::size_t end = xml.find('>', element);
  const std::string tag = xml.substr(element, end - element);
  const std::string key = " " + name + "=\"";
  const std::size_t start = tag.find(key);
  if (start == std::string::npos) return "(absent)";
  const std::size_t valueStart = start + key.size();
  return tag.substr(valueStart, tag.find('"', valueStart) - valueStart);
}

/// Reads `count` values of type T of the appended array `array`.
template <class T>
std::vector<T> appendedValues(const std::string& file, const std::string& array, std::size_t count) {
  const std::size_t marker = file.find('_', file.find("<AppendedData encoding=\"raw\">"));
  const std::size_t offset = std::stoull(arrayAttribute(file, array, "offset"));
  std::uint64_t bytes = 0;
  std::memcpy(&bytes, file.data() + marker + 1 + offset, sizeof bytes);
  EXPECT_EQ(bytes, count * sizeof(T)) << array;
  std::vector<T> values(count);
  std::memcpy(values.data(), file.data() + marker + 1 + offset + sizeof bytes, count * sizeof(T));
  return values;
}

TEST(VtkWriter, ParticlesAppendedRawReadBack) {
  const core::World world = smallWorld();
  const test::ScratchDir scratch;
  const std::filesystem::path path = scratch.path() / "p.vtp";
  core::writeParticlesVtp(path.string(), world.particles());
  const std::string file = test::readText(path);

  EXPECT_NE(file.find("<VTKFile type=\"PolyData\""), std::string::npos);
  EXPECT_NE(file.find("NumberOfPoints=\"3\""), std::string::npos);
  EXPECT_NE(file.find("NumberOfVerts=\"3\""), std::string::npos);
  for (const std::string& name : kParticleArrays) {
    EXPECT_EQ(test::countOccurrences(file, "Name=\"" + name + "\""), 1u) << name;
  }
  EXPECT_EQ(arrayAttribute(file, "velocity", "NumberOfComponents"), "3");
  EXPECT_EQ(arrayAttribute(file, "id", "type"), "UInt64");
  EXPECT_EQ(arrayAttribute(file, "material", "type"), "UInt32");

  const std::vector<double> points = appendedValues<double>(file, "position", 9);
  const std::vector<double> velocity = appendedValues<double>(file, "velocity", 9);
  const std::vector<std::uint64_t> ids = appendedValues<std::uint64_t>(file, "id", 3);
  const std::vector<std::uint32_t> materials = appendedValues<std::uint32_t>(file, "material", 3);
  const std::vector<double> radii = appendedValues<double>(file, "radius", 3);
  const std::vector<std::int64_t> offsets = appendedValues<std::int64_t>(file, "offsets", 3);
  const core::ParticleArrays& p = world.particles();
  for (std::size_t i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(points[3 * i + static_cast<std::size_t>(k)], p.position[i][k]);
      EXPECT_EQ(velocity[3 * i + static_cast<std::size_t>(k)], p.velocity[i][k]);
    }
    EXPECT_EQ(ids[i], p.id[i]);
    EXPECT_EQ(materials[i], p.material[i]);
    EXPECT_EQ(radii[i], p.radius[i]);
    EXPECT_EQ(offsets[i], static_cast<std::int64_t>(i + 1));
  }
  EXPECT_EQ(file.substr(file.size() - 11), "</VTKFile>\n");
}

TEST(VtkWriter, ParticlesAsciiReadBack) {
  const core::World world = smallWorld();
  const test::ScratchDir scratch;
  const std::filesystem::path path = scratch.path() / "p.vtp";
  core::writeParticlesVtp(path.string(), world.particles(), core::VtkEncoding::Ascii);
  const std::string file = test::readText(path);
  EXPECT_NE(file.find("NumberOfPoints=\"3\""), std::string::npos);
  EXPECT_EQ(file.find("AppendedData"), std::string::npos);
  for (const std::string& name : kParticleArrays) {
    EXPECT_EQ(arrayAttribute(file, name, "format"), "ascii") << name;
  }
  const std::size_t start = file.find('>', file.find("Name=\"position\"")) + 1;
  std::istringstream values(file.substr(start, file.find("</DataArray>", start) - start));
  for (std::size_t i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      double value = 0.0;
      values >> value;
      EXPECT_EQ(value, world.particles().position[i][k]) << "shortest round-trip text is exact";
    }
  }
}

TEST(VtkWriter, PvdListsEveryFrameInOrder) {
  const test::ScratchDir scratch;
  const std::filesystem::path path = scratch.path() / "series.pvd";
  const std::vector<core::PvdEntry> entries = {{0.0, "f_0.vtp"}, {0.05, "f_1.vtp"}, {0.1, "f&<2>.vtp"}};
  core::writePvd(path.string(), entries);
  const std::string file = test::readText(path);
  EXPECT_NE(file.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_EQ(test::countOccurrences(file, "<DataSet "), 3u);
  const std::size_t first = file.find("timestep=\"0\" group=\"\" part=\"0\" file=\"f_0.vtp\"");
  const std::size_t second = file.find("timestep=\"0.05\" group=\"\" part=\"0\" file=\"f_1.vtp\"");
  const std::size_t third = file.find("timestep=\"0.1\" group=\"\" part=\"0\" file=\"f&amp;&lt;2&gt;.vtp\"");
  ASSERT_NE(first, std::string::npos) << file;
  ASSERT_NE(second, std::string::npos) << file;
  ASSERT_NE(third, std::string::npos) << file;
  EXPECT_LT(first, second);
  EXPECT_LT(second, third);
}

TEST(VtkWriter, MeshIsWrittenAsPolygons) {
  const std::vector<core::Vec3> vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<std::array<std::uint32_t, 3>> triangles = {{0, 1, 2}, {0, 2, 3}};
  const test::ScratchDir scratch;
  const std::filesystem::path path = scratch.path() / "mesh.vtp";
  core::writeMeshVtp(path.string(), vertices, triangles);
  const std::string file = test::readText(path);
  EXPECT_NE(file.find("NumberOfPoints=\"4\""), std::string::npos);
  EXPECT_NE(file.find("NumberOfPolys=\"2\""), std::string::npos);
  EXPECT_NE(file.find("<Polys>"), std::string::npos);
  const std::vector<std::int64_t> connectivity = appendedValues<std::int64_t>(file, "connectivity", 6);
  EXPECT_EQ(connectivity, (std::vector<std::int64_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(appendedValues<std::int64_t>(file, "offsets", 2), (std::vector<std::int64_t>{3, 6}));

  const std::vector<std::array<std::uint32_t, 3>> bad = {{0, 1, 4}};
  EXPECT_THROW(core::writeMeshVtp(path.string(), vertices, bad), std::invalid_argument);
}

using test::asciiValues;

TEST(VtkWriter, DeformableSurfaceHasSpringLinesThenTrianglesAndTheirFlags) {
  // A square of four nodes: four edge springs and a diagonal (broken), two triangles (one inactive).
  const std::vector<core::Vec3> x = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<core::Vec3> u = {{0, 0, -0.5}, {0, 0, 0}, {0, 0, 0.25}, {0, 0, 0}};
  const std::vector<core::Vec3> v = {{0, 0, 1}, {0, 0, 0}, {0, 0, 0}, {2, 0, 0}};
  const std::vector<std::array<std::uint32_t, 2>> springs = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2}};
  const std::vector<char> intact = {1, 1, 1, 1, 0};
  const std::vector<std::array<std::uint32_t, 3>> triangles = {{0, 1, 2}, {0, 2, 3}};
  const std::vector<char> active = {1, 0};
  const core::DeformableFrame frame{x, u, v, springs, intact, triangles, active};
  const test::ScratchDir scratch;
  const std::filesystem::path path = scratch.path() / "sheet.vtp";
  core::writeDeformableVtp(path.string(), frame, core::VtkEncoding::Ascii);
  const std::string file = test::readText(path);
  EXPECT_NE(file.find("NumberOfPoints=\"4\""), std::string::npos);
  EXPECT_NE(file.find("NumberOfLines=\"5\""), std::string::npos);
  EXPECT_NE(file.find("NumberOfPolys=\"2\""), std::string::npos);
  EXPECT_LT(file.find("<Lines>"), file.find("<Polys>"));  // cell data order: lines, then polygons
  EXPECT_EQ(asciiValues(file, "displacement"), (std::vector<double>{0, 0, -0.5, 0, 0, 0, 0, 0, 0.25, 0, 0, 0}));
  EXPECT_EQ(asciiValues(file, "velocity"), (std::vector<double>{0, 0, 1, 0, 0, 0, 0, 0, 0, 2, 0, 0}));
  EXPECT_EQ(asciiValues(file, "intact"), (std::vector<double>{1, 1, 1, 1, 0, 1, 0}));
  EXPECT_EQ(asciiValues(file, "cell_kind"), (std::vector<double>{0, 0, 0, 0, 0, 1, 1}));
  EXPECT_EQ(arrayAttribute(file, "intact", "type"), "UInt8");
  EXPECT_EQ(asciiValues(file, "connectivity", 0), (std::vector<double>{0, 1, 1, 2, 2, 3, 3, 0, 0, 2}));
  EXPECT_EQ(asciiValues(file, "offsets", 0), (std::vector<double>{2, 4, 6, 8, 10}));
  EXPECT_EQ(asciiValues(file, "connectivity", 1), (std::vector<double>{0, 1, 2, 0, 2, 3}));

  const std::vector<std::array<std::uint32_t, 2>> bad = {{0, 4}};
  const std::vector<char> one = {1};
  EXPECT_THROW(core::writeDeformableVtp(path.string(), {x, u, v, bad, one, triangles, active}), std::invalid_argument);
  EXPECT_THROW(core::writeDeformableVtp(path.string(), {x, u, v, springs, one, triangles, active}),
               std::invalid_argument);
}

TEST(VtkWriter, TetrahedraAreAnUnstructuredGridWithStressPerCell) {
  const std::vector<core::Vec3> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  const std::vector<core::Vec3> u(5, core::Vec3(0.0, 0.0, -1e-3));
  const std::vector<core::Vec3> v(5, core::Vec3::Zero());
  const std::vector<std::vector<std::uint32_t>> elements = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  const std::vector<double> stress = {1.5e6, 2.5e5};
  const test::ScratchDir scratch;
  const std::filesystem::path path = scratch.path() / "block.vtu";
  core::writeTetrahedraVtu(path.string(), x, u, v, elements, stress, core::VtkEncoding::Ascii);
  const std::string file = test::readText(path);
  EXPECT_NE(file.find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_NE(file.find("NumberOfPoints=\"5\" NumberOfCells=\"2\""), std::string::npos);
  EXPECT_EQ(asciiValues(file, "von_mises_stress"), (std::vector<double>{1.5e6, 2.5e5}));
  EXPECT_EQ(asciiValues(file, "types"), (std::vector<double>{10, 10}));  // VTK_TETRA
  EXPECT_EQ(asciiValues(file, "offsets"), (std::vector<double>{4, 8}));
  EXPECT_EQ(asciiValues(file, "connectivity"), (std::vector<double>{0, 1, 2, 3, 1, 2, 3, 4}));

  // Appended encoding: the same stress values, bit for bit.
  core::writeTetrahedraVtu(path.string(), x, u, v, elements, stress);
  EXPECT_EQ(appendedValues<double>(test::readText(path), "von_mises_stress", 2), stress);
  const std::vector<std::vector<std::uint32_t>> triangle = {{0, 1, 2}};
  const std::vector<double> oneStress = {0.0};
  EXPECT_THROW(core::writeTetrahedraVtu(path.string(), x, u, v, triangle, oneStress), std::invalid_argument);
}

TEST(VtkWriter, UnwritablePathThrows) {
  const core::World world = smallWorld();
  const test::ScratchDir scratch;
  const std::filesystem::path path = scratch.path() / "no_such_dir" / "p.vtp";
  EXPECT_THROW(core::writeParticlesVtp(path.string(), world.particles()), std::runtime_error);
}

}  // namespace
}  // namespace demlink::server
