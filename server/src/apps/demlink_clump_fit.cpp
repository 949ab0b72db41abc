/// demlink-clump-fit: a multisphere clump template approximating a closed STL solid.
///
///   demlink-clump-fit SHAPE.stl --spheres 1,2,4,8,16 [--grid N] [--scale X] [--radii volume|inscribed]
///   demlink-clump-fit SHAPE.stl --spheres 8 --output shape_clump.json [--name NAME]
///
/// Prints the solid's exact mass properties and, for each sphere count, the relative
/// errors of the fitted clump's volume, centre of mass and principal moments, so the user
/// can choose the count; with one count and --output it writes the clump_template
/// component (docs/reference/clump_template.md) to paste into a scene's "components".
/// Method and limits: docs/clumps.md, "Fitting a template to an STL".
/// Exit codes: 0 success; 2 bad input (command line, STL file), naming the option or file.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "command_line_main.hpp"
#include "demlink/cli/command_line.hpp"
#include "demlink/core/base/input_error.hpp"
#include "demlink/core/base/names.hpp"
#include "demlink/core/particles/clump_fit.hpp"
#include "demlink/core/geometry/closed_surface.hpp"
#include "demlink/server/scene/scene_loader.hpp"
#include "demlink/v1/scene.pb.h"

namespace {

namespace cli = demlink::cli;
namespace core = demlink::core;

/// Largest STL file read [bytes]: kMaxClumpFitTriangles facets in ASCII with room to spare.
constexpr std::uintmax_t kMaxStlBytes = 128ULL << 20;
/// Most sphere counts one run compares.
constexpr std::size_t kMaxCounts = 16;

struct CommandLine {
  std::string stl;
  std::vector<std::size_t> counts;
  std::size_t grid = 64;
  double scale = 1.0;
  std::string radii = "volume";
  std::string output;
  std::string name;
};

std::vector<std::size_t> parseCounts(const std::string& text) {
  std::vector<std::size_t> counts;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    counts.push_back(cli::wholeNumber<std::size_t>("--spheres", item, 1, core::kMaxClumpTemplateSpheres));
  }
  if (counts.empty() || text.back() == ',') cli::refuse("--spheres", text, "a comma-separated list of sphere counts");
  if (counts.size() > kMaxCounts) {
    cli::refuse("--spheres", text, "at most " + std::to_string(kMaxCounts) + " counts in one run");
  }
  return counts;
}

core::StlMesh readSolid(const std::string& path) {
  const std::string field = "stl:" + path;
  std::error_code error;
  const std::uintmax_t bytes = std::filesystem::file_size(path, error);
  if (!error && bytes > kMaxStlBytes) {
    throw core::InputError(field, std::to_string(bytes) + " bytes",
                           "larger than " + std::to_string(kMaxStlBytes >> 20) + " MiB; simplify the mesh");
  }
  core::StlMesh mesh = core::readStl(path);
  if (mesh.triangles.size() > core::kMaxClumpFitTriangles) {
    throw core::InputError(field, std::to_string(mesh.triangles.size()) + " triangles",
                           "more than " + std::to_string(core::kMaxClumpFitTriangles) +
                               " triangles; simplify the mesh (a clump of at most 256 spheres needs far fewer)");
  }
  for (const std::string& warning : mesh.warnings) std::fprintf(stderr, "warning: %s: %s\n", path.c_str(), warning.c_str());
  core::requireClosedSurface(mesh, field);
  return mesh;
}

std::string vectorText(const core::Vec3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", v.x(), v.y(), v.z());
  return text;
}

void printSolid(const std::string& path, const core::StlMesh& mesh, const core::SolidMassProperties& solid,
                const core::SolidSamples& samples) {
  const auto inside = static_cast<std::size_t>(std::count(samples.inside.begin(), samples.inside.end(), 1));
  std::printf("%s: %zu triangles, closed\n", path.c_str(), mesh.triangles.size());
  std::printf("  volume                 %.9g m^3\n", solid.volume);
  std::printf("  centre of mass         %s m\n", vectorText(solid.centroid).c_str());
  std::printf("  principal moments / density %s m^5 (ascending)\n", vectorText(solid.principal.moments).c_str());
  std::printf("  principal axes         %s %s %s\n", vectorText(solid.principal.axes.col(0)).c_str(),
              vectorText(solid.principal.axes.col(1)).c_str(), vectorText(solid.principal.axes.col(2)).c_str());
  std::printf("  bounding radius        %.6g m (from the centre of mass)\n", solid.bounding_radius);
  std::printf("  grid                   %zu x %zu x %zu samples, spacing %.4g m, %zu inside\n", samples.counts[0],
              samples.counts[1], samples.counts[2], samples.spacing, inside);
}

int run(int argc, char** argv) {
  CommandLine line;
  CLI::App app("Fits a multisphere clump template to a closed STL solid and reports its mass-property errors.",
               "demlink-clump-fit");
  app.add_option("stl", line.stl, "closed STL file (ASCII or binary)")->required()->type_name("SHAPE.stl");
  cli::addValue(app, "--spheres", "sphere counts to fit, e.g. 1,2,4,8,16 (each 1.." +
                                      std::to_string(core::kMaxClumpTemplateSpheres) + ")",
                [&line](const std::string& text) { line.counts = parseCounts(text); })
      ->required()
      ->type_name("N[,N...]");
  cli::addWholeNumber(app, "--grid", line.grid, core::kMinClumpFitGridCells, core::kMaxClumpFitGridCells,
                      "grid samples along the solid's longest side (default 64)");
  cli::addNumber(app, "--scale", line.scale, {0.0, true, 1e6},
                 "metres per STL unit, e.g. 0.001 for a file in millimetres (default 1)");
  cli::addValue(app, "--radii", "volume (default): all radii scaled so the clump has the solid's volume; "
                                "inscribed: the spheres touch the surface from inside",
                [&line](const std::string& text) {
                  if (text != "volume" && text != "inscribed") cli::refuse("--radii", text, "one of volume, inscribed");
                  line.radii = text;
                })
      ->type_name("MODE");
  cli::addText(app, "--output", line.output, "write the clump_template component (JSON) here; needs one count")
      ->type_name("FILE");
  cli::addText(app, "--name", line.name, "name of the written template (default: the STL file's stem)")
      ->type_name("NAME");
  if (const std::optional<int> exitCode = cli::parse(app, argc, argv)) return *exitCode;
  if (!line.output.empty() && line.counts.size() != 1) {
    throw core::InputError("--output", line.output,
                           "writes one template: give one sphere count with --spheres (the table compares several)");
  }
  const std::string name = line.name.empty() ? std::filesystem::path(line.stl).stem().string() : line.name;
  core::requireValidName("--name", name);

  core::StlMesh mesh = readSolid(line.stl);
  for (core::Vec3& vertex : mesh.vertices) vertex *= line.scale;
  const core::SolidMassProperties solid = core::solidMassProperties(mesh, "stl:" + line.stl);
  const core::SolidSamples samples = core::sampleSolid(mesh, line.grid);
  printSolid(line.stl, mesh, solid, samples);

  const std::size_t most = *std::max_element(line.counts.begin(), line.counts.end());
  const std::vector<core::ClumpSphere> inscribed = core::inscribedSpheres(mesh, samples, most);
  std::printf("\nrelative errors of the clump (radii: %s)\n", line.radii.c_str());
  std::printf("%8s %11s %11s %11s %11s %11s %11s %10s\n", "spheres", "volume", "COM/V^1/3", "I1", "I2", "I3",
              "bound. R", "R scale");
  std::vector<core::ClumpSphere> written;
  for (const std::size_t count : line.counts) {
    std::vector<core::ClumpSphere> spheres(inscribed.begin(),
                                           inscribed.begin() + static_cast<std::ptrdiff_t>(std::min(count, inscribed.size())));
    const double scale = line.radii == "volume" ? core::volumeMatchingScale(spheres, solid.volume) : 1.0;
    for (core::ClumpSphere& sphere : spheres) {
      sphere.radius *= scale;
      sphere.offset -= solid.centroid;  // the template's frame: the solid's axes, origin at its centre of mass
    }
    core::ClumpTemplate clump(name, spheres, "--spheres");
    core::SolidMassProperties centred = solid;
    centred.centroid.setZero();
    const core::ClumpFitErrors errors = core::compareWithSolid(clump, centred);
    std::printf("%8zu %+11.3e %11.3e %+11.3e %+11.3e %+11.3e %+11.3e %10.5f%s\n", count, errors.volume,
                errors.centre_of_mass, errors.principal_moments[0], errors.principal_moments[1],
                errors.principal_moments[2], errors.bounding_radius, scale,
                spheres.size() < count ? "  (fewer: the grid is covered; try a larger --grid)" : "");
    written = spheres;
  }
  if (line.output.empty()) return 0;
  demlink::v1::ComponentDeclaration component;
  component.set_name(name);
  for (const core::ClumpSphere& sphere : written) {
    demlink::v1::ClumpSphere* member = component.mutable_clump_template()->add_spheres();
    member->mutable_offset()->set_x(sphere.offset.x());
    member->mutable_offset()->set_y(sphere.offset.y());
    member->mutable_offset()->set_z(sphere.offset.z());
    member->set_radius(sphere.radius);
  }
  std::ofstream out(line.output, std::ios::trunc);
  out << demlink::server::sceneToJson(component);
  out.close();
  if (!out) throw core::InputError("--output", line.output, "cannot be written");
  std::printf("\nwrote %s: clump_template \"%s\" with %zu spheres (offsets from the centre of mass, in m)\n",
              line.output.c_str(), name.c_str(), written.size());
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return demlink::server::runCommandLine(run, argc, argv); }
