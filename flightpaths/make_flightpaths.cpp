// aar-make-flightpaths: writes the committed flight paths conops.csv and
// characterization.csv (flightpaths/README.md) from the rig, atomically, and
// prints per-region sample counts, holds and receiver visibility.
//
//   aar-make-flightpaths --rig scenes/rig.json --out flightpaths/

#include <CLI/CLI.hpp>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/flight_path.h"
#include "aar/rig.h"
#include "flight_path_generator.h"

int main(int argc, char** argv) {
  CLI::App app{"Generate the CONOPS and characterization flight paths (deterministic)."};
  std::string rig_path;
  std::string out_dir;
  app.add_option("--rig", rig_path, "rig file (scenes/rig.json)")->required();
  app.add_option("--out", out_dir, "output folder (flightpaths/)")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    namespace fp = aar::flightpaths;
    const aar::StereoRig rig = aar::LoadRig(rig_path);
    const std::filesystem::path out(out_dir);
    aar::EnsureWritableDirectory(out);
    const auto conops = fp::GenerateConops(rig);
    const auto characterization = fp::GenerateCharacterization(rig);
    aar::WriteFileAtomic(out / "conops.csv", aar::FormatFlightPath(conops));
    aar::WriteFileAtomic(out / "characterization.csv", aar::FormatFlightPath(characterization));
    std::cout << "wrote " << (out / "conops.csv").string() << "\n" << fp::DescribeConops(rig, conops);
    std::cout << "wrote " << (out / "characterization.csv").string() << "\n"
              << fp::DescribeCharacterization(rig, characterization);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "aar-make-flightpaths: " << e.what() << "\n";
    return 1;
  }
}
