#pragma once
// Direct stereo alignment of the receiver's model: the pose that makes the
// rectified right image, read at the disparities the model has at that pose,
// match the rectified left image.
//
// Block matching and its refinement estimate one disparity per window and
// drop the windows whose texture is faint against the sensor's noise; what
// survives under noise is the band along the receiver's outline, where the
// window's bias is largest (docs/analysis.md, "The cloud's edge"). Here the
// model's surface gives every pixel it covers a disparity d(u; pose), and the
// pose is fitted to all of them at once: each pixel contributes
// r = I_R(u - d, v) - I_L(u, v), whatever its texture, weighted by it through
// the image gradient, with no window (so no window bias) and no matcher's
// filter. For Gaussian image noise of one level this is the least-squares
// pose on the images themselves.
//
// The residuals are taken at cyclopean positions c of each row: the surface
// point the model puts at left column c + d / 2 and right column c - d / 2,
// d = D(c + d / 2) the model's disparity there (a fixed point, iterated to
// 1e-4 px). Both images are then interpolated at complementary fractions,
// so linear interpolation smooths them alike and pulls no disparity towards
// whole pixels. With the model's surface at depth z along the rectified ray
// w = ((u - cx) / f, (v - cy) / f, 1), point X = z w and normal n, a small
// motion of the model, rotation omega and translation t in the rectified
// left camera's frame, moves the ray's hit by dz = n.(t + omega x X) / (n.w)
// and the disparity D = Q23 / (Q32 z) - Q33 / Q32 by -Q23 / (Q32 z^2) dz;
// at fixed c, dd = dD / (1 - s / 2) with s the slope dD/du. The residual's
// Jacobian is -g dd/dxi, g the mean horizontal gradient of the two images
// at their positions. Gauss-Newton with Huber weights (scale from the
// residuals' median absolute deviation) starts from the registered pose.
//
// Pixels used: where the model covers the pixel and its neighbours, away
// from the model's outline and its depth steps by edge_margin_px (the
// background's intensity is no part of the model), not hidden from the
// right camera by the model itself (a scanline order test on the model's
// disparities), and not at a grazing angle.
//
// What the images constrain: depth, through every covered pixel's
// disparity. The receiver's attitude shows mostly in its outline (the wing
// tips' and the tail's positions across the image), which the fit leaves
// out; seen from the tanker the nose and fuselage are a dome whose depth
// map hardly changes when it turns. So the default fit moves the
// translation alone and keeps the registration's rotation
// (DirectStereoFit::kTranslation); kPose fits all six, which removes a
// noisy cloud's tilt but turns the receiver by more noise than the
// registration has (docs/analysis.md, "Direct stereo alignment").

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>

#include "aar/analyzer/mesh.h"
#include "aar/stereo_calibration.h"

namespace aar {

/// What the fit moves: the translation alone (the registration's rotation
/// kept) or the whole pose.
enum class DirectStereoFit { kTranslation, kPose };

/// "translation" / "pose"; the parser throws aar::Error on other text.
std::string ToString(DirectStereoFit fit);
DirectStereoFit ParseDirectStereoFit(const std::string& text);

struct DirectStereoOptions {
  DirectStereoFit fit = DirectStereoFit::kTranslation;
  int iterations = 8;              ///< Gauss-Newton iterations at most
  int edge_margin_px = 2;          ///< pixels this close to the model's outline or a depth step are not used [px]
  double max_step_px = 0.5;        ///< a model disparity step between neighbours beyond this is a depth step [px]
  double min_cos_incidence = 0.2;  ///< pixels whose surface is more grazing than this (|n.w| / |w|) are not used
  double huber_k = 1.345;          ///< Huber threshold in robust standard deviations of the residual
  /// Stop when the model moves by less than this in an iteration [m] (the
  /// rotation's move at the model's extent plus the translation): the
  /// point-to-plane ICP's translation tolerance, far below the errors of
  /// interest; the steps keep jittering by about that much as the model's
  /// raster gains and loses pixels.
  double converged_m = 1e-3;
  /// The fit refines a registration that is within a fraction of a pixel
  /// in the images (its disparities, and its outline): a fit that moves a
  /// corner of the model's bounding box by more than this in column, row or
  /// disparity has left the basin where its linearised image gradients hold
  /// (a pixel or two), or slid along a direction the images hardly
  /// constrain, and is not applied [px].
  double max_motion_px = 2.0;

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

struct DirectStereoResult {
  Eigen::Isometry3d rect_left_from_receiver = Eigen::Isometry3d::Identity();
  size_t pixels = 0;            ///< pixels in the last iteration's fit
  double residual_sigma = 0.0;  ///< robust standard deviation of the last iteration's residuals [grey levels]
  int iterations = 0;
  bool converged = false;
};

/// Refines `rect_left_from_receiver` on the rectified 8-bit grey images
/// `rect_left`, `rect_right` of `region` (region-sized, top-left at the
/// image pixel region.tl()). Returns the initial pose with pixels = 0 when
/// the model covers too few usable pixels (fewer than 64) or the fit moved
/// it by more than max_motion_px.
DirectStereoResult RefineDirectStereo(const TriangleMesh& mesh, const StereoCalibration& calibration,
                                      const cv::Mat& rect_left, const cv::Mat& rect_right, const cv::Rect& region,
                                      const Eigen::Isometry3d& rect_left_from_receiver,
                                      const DirectStereoOptions& options);

}  // namespace aar
