#pragma once
/// Helpers shared by the server tests: a scratch directory per test and
/// whole-file text I/O.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace demlink::server::test {

/// An empty directory unique to the running test (and process), removed again
/// when the test passes (kept for inspection when it fails).
class ScratchDir {
 public:
  ScratchDir() {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() / (std::string("demlink_") + info->test_suite_name() + "_" +
                                                      info->name() + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    if (!::testing::Test::HasFailure()) std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  ASSERT_TRUE(out.good()) << "cannot write " << path;
}

inline std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Number of non-overlapping occurrences of `needle` in `text`.
inline std::size_t countOccurrences(const std::string& text, const std::string& needle) {
  std::size_t count = 0;
  for (std::size_t pos = text.find(needle); pos != std::string::npos; pos = text.find(needle, pos + needle.size())) {
    ++count;
  }
  return count;
}

/// The whitespace-separated values of the `occurrence`-th ASCII <DataArray Name="array"> of a VTK XML file.
inline std::vector<double> asciiValues(const std::string& xml, const std::string& array, int occurrence = 0) {
  std::size_t at = xml.find("Name=\"" + array + "\"");
  for (int k = 0; k < occurrence; ++k) at = xml.find("Name=\"" + array + "\"", at + 1);
  if (at == std::string::npos) return {};
  const std::size_t start = xml.find('>', at) + 1;
  std::istringstream values(xml.substr(start, xml.find("</DataArray>", start) - start));
  std::vector<double> out;
  for (double v = 0.0; values >> v;) out.push_back(v);
  return out;
}

/// A small valid scene (JSON): a box with a floor, one material and a 2x2x2
/// lattice; end_time and vtk_interval as given [s].
/// A command-line program's exit code and its stdout and stderr together.
struct ProgramRun {
  int exit_code = -1;
  std::string output;
};

/// Runs `program` with `arguments` (each passed quoted); the output is captured in dir/tool.log.
inline ProgramRun runProgram(const std::string& program, const std::vector<std::string>& arguments,
                             const std::filesystem::path& dir) {
  const std::filesystem::path log = dir / "tool.log";
  // Built with append(): GCC 12 reports a false -Wrestrict for `"literal" + std::string` at -O3.
  std::string command;
  command.append("\"").append(program).append("\"");
  for (const std::string& argument : arguments) command.append(" \"").append(argument).append("\"");
  command.append(" > \"").append(log.string()).append("\" 2>&1");
  const int status = std::system(command.c_str());
  ProgramRun run;
  if (status != -1 && WIFEXITED(status)) run.exit_code = WEXITSTATUS(status);
  run.output = readText(log);
  return run;
}

inline std::string tinySceneJson(double endTime, double vtkInterval) {
  return R"({"components": [
    {"name": "box", "simulation_box": {"time_step": 1e-5, "restitution_tolerance": 0.2, "end_time": )" + std::to_string(endTime) +
         R"(, "output": {"vtk_interval": )" + std::to_string(vtkInterval) + R"(, "progress_interval_s": 60}}},
    {"name": "glass", "material": {"density": 2500, "youngs_modulus": 5e6}},
    {"name": "floor", "plane": {"normal": {"z": 1}, "material": "glass"}},
    {"name": "spheres", "particle_lattice": {"material": "glass", "radius": 0.002, "spacing": 0.006,
      "origin": {"x": 0.01, "y": 0.01, "z": 0.003}, "counts": {"nx": 2, "ny": 2, "nz": 2}}}
  ]})";
}

}  // namespace demlink::server::test
