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
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "demlink/cli/command_line.hpp"
#include "fmu_config.hpp"
#include "zip_writer.hpp"

int main(int argc, char** argv) {
  std::string config_path;
  std::string output;
  std::string fmu_library = DEMLINK_FMU_LIBRARY;
  std::string win64_library;
  bool print_only = false;
  CLI::App app("Packages a DEMLink component set as an FMI 2.0 Co-Simulation FMU (docs/fmi.md).", "demlink-fmu");
  app.add_option("CONFIG", config_path, "the FMU configuration (docs/fmi.md)")->required()->type_name("FILE");
  demlink::cli::addText(app, "-o", output, "the FMU to write")->type_name("OUTPUT.fmu");
  demlink::cli::addText(app, "--fmu-library", fmu_library,
                        "the generic FMU library (default: the one built with this tool)")
      ->type_name("PATH");
  demlink::cli::addText(app, "--win64-library", win64_library,
                        "the win64 FMU library demlink_fmu.dll (default: none, linux64 only)")
      ->type_name("PATH");
  app.add_flag("--model-description", print_only, "print modelDescription.xml and exit");
  if (const std::optional<int> exitCode = demlink::cli::parse(app, argc, argv)) return *exitCode;
  if (output.empty() && !print_only) {
    std::cerr << "error: -o: the FMU to write is required (or --model-description)\n"
              << "(demlink-fmu --help lists the options)\n";
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
