// aar-make-flightpaths: writes the committed flight paths conops.csv and
// characterization.csv (flightpaths/README.md) from the rig, atomically, and
// prints per-region sample counts, holds and receiver visibility.
//
//   aar-make-flightpaths --rig scenes/rig.json --out flightpaths/
//   aar-make-flightpaths --rig scenes/rig-thesis.json --out flightpaths/ --paths conops-level
//   aar-make-flightpaths --rig scenes/rig.json --out flightpaths/ --paths conops-boom

#include <CLI/CLI.hpp>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

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
  std::vector<std::string> paths = {"conops", "characterization"};
  app.add_option("--paths", paths,
                 "paths to write: conops, characterization, conops-boom (with scenes/rig.json), conops-level (with "
                 "scenes/rig-thesis.json)")
      ->check(CLI::IsMember({"conops", "characterization", "conops-level", "conops-boom"}));
  CLI11_PARSE(app, argc, argv);
  try {
    namespace fp = aar::flightpaths;
    const aar::StereoRig rig = aar::LoadRig(rig_path);
    const std::filesystem::path out(out_dir);
    aar::EnsureWritableDirectory(out);
    for (const std::string& name : paths) {
      const std::filesystem::path file = out / (name + ".csv");
      if (name == "characterization") {
        const auto characterization = fp::GenerateCharacterization(rig);
        aar::WriteFileAtomic(file, aar::FormatFlightPath(characterization));
        std::cout << "wrote " << file.string() << "\n" << fp::DescribeCharacterization(rig, characterization);
      } else {
        auto conops =
            name == "conops-level" ? fp::GenerateConops(rig, fp::LevelConopsOptions()) : fp::GenerateConops(rig);
        if (name == "conops-boom") conops = fp::AddBoomSchedule(rig, std::move(conops));
        aar::WriteFileAtomic(file, aar::FormatFlightPath(conops));
        std::cout << "wrote " << file.string() << "\n" << fp::DescribeConops(rig, conops);
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "aar-make-flightpaths: " << e.what() << "\n";
    return 1;
  }
}
