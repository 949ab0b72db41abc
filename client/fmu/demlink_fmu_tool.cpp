/// demlink-fmu: packages a DEMLink component set as an FMI 2.0 Co-Simulation FMU
/// (docs/fmi.md). Reads the FMU configuration, writes modelDescription.xml, copies the
/// generic FMU library (the C ABI compiled in) as binaries/linux64/<model>.so and the
/// configuration as resources/demlink_fmu.cfg, and zips them into the .fmu. With
/// --win64-library the FMU also holds the cross-built Windows library as
/// binaries/win64/<model>.dll.
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "fmu_config.hpp"
#include "zip_writer.hpp"

namespace {

constexpr const char* kUsage =
    "usage: demlink-fmu CONFIG -o OUTPUT.fmu [--fmu-library PATH] [--win64-library PATH]\n"
    "  CONFIG         the FMU configuration (docs/fmi.md)\n"
    "  -o OUTPUT.fmu  the FMU to write\n"
    "  --fmu-library  the generic FMU library (default: the one built with this tool)\n"
    "  --win64-library  the win64 FMU library demlink_fmu.dll (default: none, linux64 only)\n"
    "  --model-description  print modelDescription.xml and exit\n";

}  // namespace

int main(int argc, char** argv) {
  std::string config_path;
  std::string output;
  std::string fmu_library = DEMLINK_FMU_LIBRARY;
  std::string win64_library;
  bool print_only = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool hasValue = i + 1 < argc;
    if (arg == "-h" || arg == "--help") {
      std::cout << kUsage;
      return 0;
    }
    if (arg == "-o" && hasValue) {
      output = argv[++i];
    } else if (arg == "--fmu-library" && hasValue) {
      fmu_library = argv[++i];
    } else if (arg == "--win64-library" && hasValue) {
      win64_library = argv[++i];
    } else if (arg == "--model-description") {
      print_only = true;
    } else if (config_path.empty() && !arg.starts_with("-")) {
      config_path = arg;
    } else {
      std::cerr << "demlink-fmu: unexpected argument '" << arg << "'\n" << kUsage;
      return 2;
    }
  }
  if (config_path.empty() || (output.empty() && !print_only)) {
    std::cerr << kUsage;
    return 2;
  }
  try {
    const std::string text = demlink::fmu::readFile(config_path);
    const demlink::fmu::FmuConfig config = demlink::fmu::parseConfig(text);
    const std::string description = demlink::fmu::modelDescriptionXml(config, demlink::fmu::guidOf(text));
    if (print_only) {
      std::cout << description;
      return 0;
    }
    std::vector<demlink::fmu::ZipEntry> entries = {
        {"modelDescription.xml", description},
        {"binaries/linux64/" + config.model_identifier + ".so", demlink::fmu::readFile(fmu_library)},
    };
    if (!win64_library.empty()) {
      entries.push_back({"binaries/win64/" + config.model_identifier + ".dll", demlink::fmu::readFile(win64_library)});
    }
    entries.push_back({"resources/demlink_fmu.cfg", text});
    std::ofstream out(output, std::ios::binary | std::ios::trunc);
    const std::string archive = demlink::fmu::zipArchive(entries);
    out.write(archive.data(), static_cast<std::streamsize>(archive.size()));
    if (!out) throw std::invalid_argument("cannot write '" + output + "'");
    std::cout << "demlink-fmu: wrote " << output << " (" << config.model_identifier << ", "
              << demlink::fmu::variablesOf(config).size() << " variables)\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "demlink-fmu: " << e.what() << "\n";
    return 1;
  }
}
