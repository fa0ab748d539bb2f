// The lighting constants of the scene and background shaders
// (docs/rendering.md, "The sun" and "Daylight"): the sun's direction in the
// tanker frame, and with --daylight the sun's light, the sky's radiance and
// Preetham's sky from daylight.h's model.

#include "aar/renderer/daylight.h"
#include "aar/renderer/scene_renderer.h"

namespace aar {
namespace {

// The mean albedo of what lies below: the mip chain's last (1 x 1) level of
// the terrain or cloud texture, or the plain ground's.
Eigen::Vector3d SurfaceAlbedo(const TextureMips* surface) {
  if (!surface) return {kPlainGroundAlbedo[0], kPlainGroundAlbedo[1], kPlainGroundAlbedo[2]};
  const std::vector<uint8_t>& texel = surface->levels.back();
  Eigen::Vector3d albedo;
  for (int c = 0; c < 3; ++c) albedo[c] = SrgbToLinear(texel[c] / 255.0f);
  return albedo;
}

}  // namespace

void SceneRenderer::SetLightConstants(const TextureMips* surface) {
  // scene.frag: ids 0-2 the sun's direction; 3-12 daylight's; 13-21 the floodlight's.
  const Eigen::Vector3f sun = sun_direction_in_tanker_.cast<float>();
  for (int i = 0; i < 3; ++i) scene_constants_.AddFloat(sun[i]);
  const BackgroundOptions& bg = options_.background;
  if (bg.daylight) SetDaylightConstants(surface);
  if (!options_.floodlight) return;
  // 13 on; 14-16 its place, 17-19 its axis; 20 its intensity in the units
  // of the sun's light at 1 m (0.75 per 133,800 lx, daylight.h), at the
  // render scale; 21 the beam's sigma.
  const Floodlight& f = *options_.floodlight;
  scene_constants_.AddIntAt(13, 1);
  for (int i = 0; i < 3; ++i) scene_constants_.AddFloatAt(14 + i, static_cast<float>(f.position_in_tanker[i]));
  for (int i = 0; i < 3; ++i) scene_constants_.AddFloatAt(17 + i, static_cast<float>(f.axis_in_tanker[i]));
  const double units = f.intensity_cd * 0.75 / kSolarIlluminanceLx * RenderScale(bg);
  scene_constants_.AddFloatAt(20, static_cast<float>(units));
  scene_constants_.AddFloatAt(21, static_cast<float>(f.sigma_rad));
}

void SceneRenderer::SetDaylightConstants(const TextureMips* surface) {
  // scene.frag: 3 daylight on; 4-6 the sun's light; 7-9 and 10-12 the sky's
  // radiance A + B w.z per channel.
  const BackgroundOptions& bg = options_.background;
  const Daylight d = ComputeDaylight(bg, SurfaceAlbedo(surface));
  const Eigen::Vector3d sky_a = 0.5 * (d.sky_from_above + d.sky_from_below);
  const Eigen::Vector3d sky_b = 0.75 * (d.sky_from_above - d.sky_from_below);
  scene_constants_.AddInt(1);
  for (const Eigen::Vector3d* v : {&d.sun_at_tanker, &sky_a, &sky_b}) {
    for (int c = 0; c < 3; ++c) scene_constants_.AddFloat(static_cast<float>((*v)[c]));
  }
  // background.frag: 0 daylight on; 1-15 Perez A..E, each for Y, x, y;
  // 16-18 the zenith over its Perez value; 19-21 the surface's light;
  // 22-24 the sun's disc; 25 its angular radius.
  background_constants_.AddInt(1);
  for (int k = 0; k < 5; ++k) {
    for (int channel = 0; channel < 3; ++channel) background_constants_.AddFloat(d.sky.perez[channel][k]);
  }
  const Eigen::Vector3d zenith = d.sky.ZenithOverPerez();
  for (const Eigen::Vector3d* v : {&zenith, &d.surface_light, &d.sun_disc}) {
    for (int c = 0; c < 3; ++c) background_constants_.AddFloat(static_cast<float>((*v)[c]));
  }
  background_constants_.AddFloat(static_cast<float>(d.disc_radius_rad));
}

}  // namespace aar
