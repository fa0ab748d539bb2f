// The background's single-sample pass and its cache (docs/rendering.md,
// "Backgrounds"): the push constants of shaders/background.frag for a
// camera, and the camera's background, rendered the first time and then
// served from the cache.

#include <chrono>
#include <string>

#include "aar/progress.h"
#include "aar/renderer/background_texture.h"
#include "aar/renderer/scene_renderer.h"

namespace aar {

SceneRenderer::BackgroundPush SceneRenderer::BackgroundFor(const Camera& camera) const {
  static_assert(sizeof(BackgroundPush) == 96, "must match background.frag's block");
  const BackgroundOptions& bg = options_.background;
  const Eigen::Matrix3d level_from_pixel = LevelFromPixel(camera, bg);
  const Eigen::Vector3d camera_above_ground = CameraAboveGround(camera, bg);
  BackgroundPush push{};
  for (int row = 0; row < 3; ++row) {
    push.level_from_pixel_rows[row] = glm::vec4(level_from_pixel(row, 0), level_from_pixel(row, 1),
                                                level_from_pixel(row, 2), camera_above_ground[row]);
  }
  const Eigen::Vector3d sun = SunInLevel(bg);
  push.sun_in_level = glm::vec4(sun.x(), sun.y(), sun.z(), 3.912 / bg.visibility_m);
  // The surface the rays meet: the ground, or the top of the cloud deck.
  const double surface_m = bg.kind == BackgroundKind::kClouds ? bg.cloud_top_m : 0.0;
  const double h = camera_above_ground.z() - surface_m;
  const double r = kEarthRadiusM + surface_m;
  push.surface = glm::vec4(h * (2.0 * r + h) / ((r + h) * (r + h)), h * (2.0 * r + h) / (r + h), surface_m,
                           bg.haze_scale_height_m);
  const bool clouds = bg.kind == BackgroundKind::kClouds;
  const double tile_m = clouds ? kCloudTextureSize * bg.cloud_texel_m : kTerrainTextureSize * bg.ground_texel_m;
  const float kind = bg.kind == BackgroundKind::kSky ? 1.0f : clouds ? 3.0f : 2.0f;
  // Daylight's sun disc: its edge spread over one pixel's angle at the image centre.
  const double pixel_rad = bg.daylight ? 1.0 / camera.intrinsics.fx_px : 0.0;
  push.texture_map = glm::vec4(1.0 / tile_m, pixel_rad, 0.0f, kind);
  return push;
}

const std::vector<float>& SceneRenderer::BackgroundOf(const Camera& camera, ViewTimings* timings) {
  const BackgroundPush push = BackgroundFor(camera);
  const std::string key(reinterpret_cast<const char*>(&push), sizeof(push));
  for (const CachedBackground& cached : backgrounds_) {
    if (cached.push == key) return cached.rgb;
  }
  // A single-sample pass over the whole frame, evaluated at the pixel centres.
  auto start = std::chrono::steady_clock::now();
  Target& single = TargetFor(1, false);
  const PixelRect full{0, 0, width_, height_};
  context_.SubmitAndWait(
      [&](VkCommandBuffer cmd) { Record(cmd, single, Eigen::Matrix4d::Identity(), {}, false, full, &push); });
  if (timings) timings->render_ms += MillisecondsSince(start);
  start = std::chrono::steady_clock::now();
  ReadBack(single, full);
  const auto* half = static_cast<const Eigen::half*>(readback_.mapped());
  std::vector<float> rgb(static_cast<size_t>(width_) * height_ * 3);
  for (size_t i = 0; i < rgb.size() / 3; ++i) {
    for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = static_cast<float>(half[i * 4 + c]);
  }
  if (timings) timings->readback_ms += MillisecondsSince(start);
  if (backgrounds_.size() == kCachedBackgrounds) backgrounds_.erase(backgrounds_.begin());
  backgrounds_.push_back({key, std::move(rgb)});
  return backgrounds_.back().rgb;
}

}  // namespace aar
