#pragma once
// Lens flare's ghosts of the sun (docs/rendering.md, "Lens flare"): light
// of the sun reflected twice between the lens's surfaces reaches the sensor
// out of focus, as discs (images of the aperture) on the line from the
// image centre through the sun's image. A view effect on the pinhole
// render, after the veiling glare and before the lens's resampling and the
// sensor, where the rig's sensor declares flare_ghosts. Pure CPU; the
// ghosts depend on the camera and the sun alone, so they are computed once
// per camera and added to every frame.

#include <Eigen/Core>
#include <vector>

#include "aar/renderer/view_effect.h"
#include "aar/rig.h"
#include "aar/sensor.h"

namespace aar {

class LensFlare : public ViewEffect {
 public:
  /// `camera`, `sun_in_tanker`, `sun_light` as for SunGlare (sun_glare.h).
  /// Each ghost is a disc of radius_px centred at c + position (s - c), c
  /// the principal point and s where the sun projects, of uniform radiance
  /// that spreads fraction x pi S cos(alpha) (the sun's irradiance on the
  /// aperture) over the disc's solid angle, its edge antialiased over a
  /// pixel; the part of a disc beyond the image is lost. No ghost with the
  /// sun behind the lens.
  LensFlare(const Camera& camera, const Eigen::Vector3d& sun_in_tanker, const Eigen::Vector3d& sun_light,
            const std::vector<FlareGhost>& ghosts);

  LinearImage Apply(const LinearImage& radiance, const SensorExposure& exposure) const override;
  /// The ghosts' radiance added to each pixel, linear RGB, row-major.
  const std::vector<float>& image() const { return image_; }
  /// Each ghost's centre in the pinhole render [px] (empty with the sun behind the lens).
  const std::vector<Eigen::Vector2d>& centres_px() const { return centres_px_; }

 private:
  int width_ = 0, height_ = 0;
  std::vector<float> image_;
  std::vector<Eigen::Vector2d> centres_px_;
};

}  // namespace aar
