/// demlink-clump-fit as a user runs it: the error table, the written template loaded
/// through the scene parser (the same spheres the engine's fit gives), and exit code 2
/// naming the file or option for bad input.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>

#include "demlink/core/particles/clump_fit.hpp"
#include "demlink/core/geometry/closed_surface.hpp"
#include "scene_test_support.hpp"
#include "test_support.hpp"

namespace demlink::server {
namespace {

using Result = test::ProgramRun;

Result runFit(const std::vector<std::string>& arguments, const std::filesystem::path& dir) {
  return test::runProgram(DEMLINK_CLUMP_FIT_EXE, arguments, dir);
}

const std::string kRock = std::string(DEMLINK_EXAMPLES_DIR) + "/scenes/meshes/rock.stl";

TEST(DemlinkClumpFit, PrintsOneErrorRowPerSphereCount) {
  const test::ScratchDir scratch;
  const Result result = runFit({kRock, "--spheres", "1,4,16", "--grid", "40"}, scratch.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("320 triangles, closed"), std::string::npos) << result.output;
  for (const char* row : {"\n       1 ", "\n       4 ", "\n      16 "}) {
    EXPECT_NE(result.output.find(row), std::string::npos) << row << result.output;
  }
}

TEST(DemlinkClumpFit, WrittenTemplateLoadsThroughTheSceneParser) {
  const test::ScratchDir scratch;
  const std::filesystem::path out = scratch.path() / "rock8.json";
  const Result result = runFit({kRock, "--spheres", "8", "--grid", "40", "--output", out.string(), "--name", "rock8"},
                               scratch.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const v1::Scene scene = test::sceneOf(
      {R"({"name": "box", "simulation_box": {"end_time": 0.1}})", R"({"name": "granite", "material": {}})",
       test::readText(out),
       R"({"name": "rocks", "particle_lattice": {"material": "granite", "clump_template": "rock8",
           "origin": {"z": 0.05}, "spacing": 0.05, "counts": {"nx": 2, "ny": 1, "nz": 1}}})"});
  const TranslatedScene translated = translateScene(scene, {});
  ASSERT_EQ(translated.world.clumpTemplates().size(), 1u);
  const core::ClumpTemplate& loaded = translated.world.clumpTemplates()[0];
  EXPECT_EQ(loaded.name(), "rock8");
  EXPECT_EQ(translated.world.clumps().size(), 2u);

  // The engine's fit of the same file with the same grid, in the frame the tool writes
  // (origin at the solid's centre of mass).
  const core::StlMesh mesh = core::readStl(kRock);
  core::requireClosedSurface(mesh, "rock");
  const core::SolidMassProperties solid = core::solidMassProperties(mesh, "rock");
  std::vector<core::ClumpSphere> spheres = core::inscribedSpheres(mesh, core::sampleSolid(mesh, 40), 8);
  const double scale = core::volumeMatchingScale(spheres, solid.volume);
  ASSERT_EQ(loaded.spheres().size(), spheres.size());
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    EXPECT_LT((loaded.spheres()[k].offset - (spheres[k].offset - solid.centroid)).norm(), 1e-15) << k;
    EXPECT_NEAR(loaded.spheres()[k].radius, scale * spheres[k].radius, 1e-15) << k;
  }
  EXPECT_NEAR(loaded.volume(), solid.volume, 1e-4 * solid.volume);
}

/// Exit code 2 and a message holding `expected`.
void expectRefused(const std::vector<std::string>& arguments, const std::string& expected,
                   const std::filesystem::path& dir) {
  const Result result = runFit(arguments, dir);
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(expected), std::string::npos) << "expected '" << expected << "' in: " << result.output;
}

TEST(DemlinkClumpFit, BadInputExitsTwoNamingTheFileOrOption) {
  const test::ScratchDir scratch;
  const std::filesystem::path& dir = scratch.path();
  test::writeText(dir / "empty.stl", "");
  test::writeText(dir / "text.stl", "this is not an STL file\n");
  // A tetrahedron with one face missing.
  test::writeText(dir / "open.stl", R"(solid open
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 1 0
vertex 1 0 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 1 0 0
vertex 0 0 1
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 0 1
vertex 0 1 0
endloop
endfacet
endsolid open
)");
  const std::string missing = (dir / "missing.stl").string();
  expectRefused({missing, "--spheres", "4"}, missing, dir);
  expectRefused({(dir / "empty.stl").string(), "--spheres", "4"}, "file is empty", dir);
  expectRefused({(dir / "text.stl").string(), "--spheres", "4"}, "not an ASCII STL", dir);
  expectRefused({(dir / "open.stl").string(), "--spheres", "4"}, "the surface is open", dir);
  expectRefused({kRock, "--spheres", "0"}, "--spheres = 0", dir);
  expectRefused({kRock, "--spheres", "100000"}, "--spheres = 100000", dir);
  expectRefused({kRock, "--spheres", "2,x"}, "--spheres = x", dir);
  expectRefused({kRock, "--spheres", "2,"}, "--spheres = 2,", dir);
  expectRefused({kRock}, "--spheres is required", dir);
  expectRefused({kRock, "--spheres", "4", "--grid", "3"}, "--grid = 3", dir);
  expectRefused({kRock, "--spheres", "4", "--scale", "-1"}, "--scale = -1", dir);
  expectRefused({kRock, "--spheres", "4", "--radii", "largest"}, "--radii = largest", dir);
  expectRefused({kRock, "--spheres", "2,4", "--output", (dir / "x.json").string()}, "--output", dir);
  expectRefused({kRock, "--spheres", "4", "--name", "a/b"}, "--name", dir);
}

}  // namespace
}  // namespace demlink::server
