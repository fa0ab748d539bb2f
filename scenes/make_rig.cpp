// aar-make-rig: writes the committed stereo rigs scenes/rig.json (cameras
// 30 deg down), scenes/rig-thesis.json (41 deg down, issue 9) and
// scenes/rig-distorted.json (rig.json with lens distortion) and
// scenes/rig-noisy.json (rig.json with an image sensor),
// scenes/rig-rolling.json (its sensor with a rolling shutter) and
// scenes/rig-1080p.json, scenes/rig-2160p.json (rig.json's cameras at
// higher resolutions) and scenes/rig-lwir.json (a thermal pair) from their
// presets (rig_presets.h), atomically.
//
//   aar-make-rig --out scenes/

#include <CLI/CLI.hpp>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>

#include "aar/file_io.h"
#include "aar/rig.h"
#include "rig_presets.h"

int main(int argc, char** argv) {
  CLI::App app{
      "Generate the committed stereo rigs rig.json, rig-thesis.json, rig-distorted.json, rig-noisy.json, "
      "rig-rolling.json, rig-1080p.json, rig-2160p.json and rig-lwir.json (deterministic)."};
  std::string out_dir = "scenes";
  app.add_option("--out", out_dir, "output folder (scenes/)");
  CLI11_PARSE(app, argc, argv);
  try {
    namespace sc = aar::scenes;
    const std::filesystem::path out(out_dir);
    aar::EnsureWritableDirectory(out);
    for (const auto& [name, preset] :
         {std::pair{"rig.json", sc::DefaultRig()}, std::pair{"rig-thesis.json", sc::ThesisRig()},
          std::pair{"rig-distorted.json", sc::DistortedRig()}, std::pair{"rig-noisy.json", sc::NoisyRig()},
          std::pair{"rig-rolling.json", sc::RollingRig()}, std::pair{"rig-1080p.json", sc::Rig1080p()},
          std::pair{"rig-2160p.json", sc::Rig2160p()}, std::pair{"rig-lwir.json", sc::LwirRig()}}) {
      const std::filesystem::path path = out / name;
      aar::WriteFileAtomic(path, sc::FormatRig(preset));
      const aar::StereoRig rig = aar::LoadRig(path);  // the written file reads back as a rig
      std::cout << "wrote " << path.string() << ": cameras " << preset.pitch_down_deg << " deg down, contact "
                << (rig.contact_position_m - rig.left.tanker_from_camera.translation()).norm()
                << " m from the left camera\n";
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "aar-make-rig: " << e.what() << "\n";
    return 1;
  }
}
