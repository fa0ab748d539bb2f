// aar-make-scenes: writes the binary glTF models used by the renderer
// (receiver c12.glb and its propeller c12_propeller.glb, tanker kc46.glb, its boom kc46_boom.glb and
// kc46_boom_tube.glb, calib_board.glb) deterministically, and
// prints their measurements (body axes) for docs/scenes.md.
//
//   aar-make-scenes --out scenes/

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "c12.h"
#include "c12_airframe.h"
#include "c12_propeller.h"
#include "calib_board.h"
#include "glb_writer.h"
#include "kc46.h"
#include "kc46_boom.h"

namespace {

using namespace aar::scenes;

struct Options {
  std::filesystem::path out_dir = "scenes";  ///< where the .glb files go
  C12Options c12;                            ///< receiver texture settings (atlas 2048, 64 levels, fixed seed)
  BoardSpec board;                           ///< thesis board: 16 x 17 inner corners, 0.5 m squares
};

void PrintBox(const char* label, const Box3& b) {
  const Vec3 size = b.size();
  std::printf("  %-11s x [%8.3f, %8.3f]  y [%8.3f, %8.3f]  z [%8.3f, %8.3f]  size %.3f x %.3f x %.3f m\n", label,
              b.min.x(), b.max.x(), b.min.y(), b.max.y(), b.min.z(), b.max.z(), size.x(), size.y(), size.z());
}

/// Prints per-node and whole-model triangle counts, bounding boxes (body
/// axes), enclosed volumes and, for textured models, texel densities.
void Report(const SceneModel& scene, const std::filesystem::path& file, int atlas_size) {
  std::printf("%s: %s, %ju bytes (%.2f MiB)\n", scene.name.c_str(), file.string().c_str(),
              static_cast<std::uintmax_t>(std::filesystem::file_size(file)),
              static_cast<double>(std::filesystem::file_size(file)) / (1024.0 * 1024.0));
  std::vector<Vec3> all;
  std::size_t triangles = 0;
  for (const Node& node : scene.nodes) {
    Mesh merged;
    for (const Primitive& prim : node.primitives) {
      const auto base = static_cast<std::uint32_t>(merged.positions.size());
      merged.positions.insert(merged.positions.end(), prim.mesh.positions.begin(), prim.mesh.positions.end());
      merged.uvs.insert(merged.uvs.end(), prim.mesh.uvs.begin(), prim.mesh.uvs.end());
      for (std::uint32_t i : prim.mesh.indices) merged.indices.push_back(base + i);
    }
    std::printf("  node %-16s %6zu triangles, %6zu vertices, volume %8.3f m^3, area %8.2f m^2", node.name.c_str(),
                merged.TriangleCount(), merged.positions.size(), SignedVolume(merged), SurfaceArea(merged));
    if (!merged.uvs.empty()) {
      const TexelDensity d = MeasureTexelDensity(merged, atlas_size, atlas_size, 60.0);
      std::printf(", texels/m p01 %.0f median %.0f, area < 60/m %.2f %%", d.p01_per_m, d.median_per_m,
                  100.0 * d.share_below);
    }
    std::printf("\n");
    PrintBox("", BoundingBox(merged.positions));
    all.insert(all.end(), merged.positions.begin(), merged.positions.end());
    triangles += merged.TriangleCount();
  }
  std::printf("  total %zu triangles, %zu vertices\n", triangles, all.size());
  PrintBox("bbox (body)", BoundingBox(all));
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"Writes the receiver (C-12) and its propeller, tanker (KC-46), boom and calibration board glTF models."};
  app.add_option("--out", options.out_dir, "Output directory")->capture_default_str();
  app.add_option("--atlas-size", options.c12.atlas_size, "C-12 texture atlas size (texels, square)")
      ->capture_default_str()
      ->check(CLI::Range(256, 8192));
  CLI11_PARSE(app, argc, argv);

  try {
    std::filesystem::create_directories(options.out_dir);
    const auto start = std::chrono::steady_clock::now();

    C12Info info;
    const SceneModel c12 = BuildC12(options.c12, &info);
    const auto c12_path = options.out_dir / "c12.glb";
    WriteGlb(c12, c12_path);
    Report(c12, c12_path, options.c12.atlas_size);
    std::printf("  reference point (origin): %.3f m aft of the nose tip; wing MAC %.3f m at |y| = %.3f m\n",
                info.reference_station_m, info.mac_m, info.mac_span_station_m);
    std::printf("  texture %dx%d RGB PNG, %zu bytes, nominal %.1f texels/m, %d levels per channel\n",
                options.c12.atlas_size, options.c12.atlas_size, c12.texture_png.size(), info.texels_per_m,
                options.c12.colour_levels);

    CheckPropellerHubs(MakeC12Airframe());
    const SceneModel propeller = BuildC12Propeller();
    const auto propeller_path = options.out_dir / "c12_propeller.glb";
    WriteGlb(propeller, propeller_path);
    Report(propeller, propeller_path, 0);

    RigClearance clearance;
    const SceneModel kc46 = BuildKc46(&clearance);
    const auto kc46_path = options.out_dir / "kc46.glb";
    WriteGlb(kc46, kc46_path);
    Report(kc46, kc46_path, 0);
    std::printf(
        "  rig clearance: fuselage underside at x=-20: z=%.3f m; lowest point near the cameras: z=%.3f m; "
        "points inside the cameras' view: %zu\n",
        clearance.fuselage_bottom_at_rig_m, clearance.lowest_near_rig_m, clearance.vertices_in_view);

    for (const SceneModel& boom : {BuildKc46Boom(), BuildKc46BoomTube()}) {
      const auto boom_path = options.out_dir / (boom.name + ".glb");
      WriteGlb(boom, boom_path);
      Report(boom, boom_path, 0);
    }

    const SceneModel board = BuildCalibBoard(options.board);
    const auto board_path = options.out_dir / "calib_board.glb";
    WriteGlb(board, board_path);
    Report(board, board_path, 0);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("generated in %.1f s\n", seconds);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aar-make-scenes: %s\n", e.what());
    return 1;
  }
  return 0;
}
