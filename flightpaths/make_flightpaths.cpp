// aar-make-flightpaths: writes the committed flight paths conops.csv and
// characterization.csv (flightpaths/README.md) from the rig, atomically, and
// prints per-region sample counts, holds and receiver visibility.
//
//   aar-make-flightpaths --rig scenes/rig.json --out flightpaths/
//   aar-make-flightpaths --rig scenes/rig-thesis.json --out flightpaths/ --paths conops-level
//   aar-make-flightpaths --rig scenes/rig.json --out flightpaths/ --paths conops-boom
//   aar-make-flightpaths --rig scenes/rig.json --out /tmp/125hz --paths conops --time-step 0.008
//   aar-make-flightpaths --rig scenes/rig.json --out /tmp/heldout --paths conops --variant 7

#include <CLI/CLI.hpp>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
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
  double time_step_s = aar::flightpaths::ConopsOptions{}.time_step_s;
  app.add_option("--time-step", time_step_s,
                 "sample spacing of the CONOPS paths [s] (e.g. 0.008 for a 125 Hz camera; the committed files use "
                 "the default)")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 10.0));
  std::optional<uint64_t> variant;
  app.add_option("--variant", variant,
                 "write the seeded variant SEED of the CONOPS approach (conops_variant.h) as conops-variant-SEED.csv "
                 "(with --paths conops-boom: conops-boom-variant-SEED.csv, the boom's schedule on it), for held-out "
                 "tests");
  CLI11_PARSE(app, argc, argv);
  try {
    namespace fp = aar::flightpaths;
    const aar::StereoRig rig = aar::LoadRig(rig_path);
    const std::filesystem::path out(out_dir);
    aar::EnsureWritableDirectory(out);
    for (const std::string& name : paths) {
      const std::filesystem::path file = out / (name + ".csv");
      if (variant) {
        if (name != "conops" && name != "conops-boom") {
          throw aar::Error("--variant: only the conops and conops-boom paths have variants, not " + name);
        }
        const std::string stem = name + "-variant-" + std::to_string(*variant);
        auto samples = fp::GenerateConops(rig, fp::ConopsVariantOptions(rig, *variant, time_step_s));
        if (name == "conops-boom") samples = fp::AddBoomSchedule(rig, std::move(samples));
        const std::filesystem::path variant_file = out / (stem + ".csv");
        aar::WriteFileAtomic(variant_file, aar::FormatFlightPath(samples));
        std::cout << "wrote " << variant_file.string() << "\n" << fp::DescribeConops(rig, samples);
        continue;
      }
      if (name == "characterization") {
        const auto characterization = fp::GenerateCharacterization(rig);
        aar::WriteFileAtomic(file, aar::FormatFlightPath(characterization));
        std::cout << "wrote " << file.string() << "\n" << fp::DescribeCharacterization(rig, characterization);
      } else {
        fp::ConopsOptions options = name == "conops-level" ? fp::LevelConopsOptions() : fp::ConopsOptions();
        options.time_step_s = time_step_s;
        auto conops = fp::GenerateConops(rig, options);
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
