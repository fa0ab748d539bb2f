#pragma once
// The matching window's bias on a curved surface, predicted from the model.
//
// The sub-pixel refinement (subpixel.h) fits one shift, or an affine shift
// field with slanted windows, to all samples of its window. On a curved
// surface the true disparity field is not affine over the window, and the
// refinement returns, to first order, its least-squares affine fit weighted
// by the texture: for a Gauss-Newton fixed point with residual
// e_s = g_s (d(s) - shift(s)) + c, the parameters are
// p = (J^T J)^{-1} J^T (g o d), J the zero-mean Jacobian rows g_s (1, j, i)
// and g_s the mean horizontal gradient of the two windows at sample s. On a
// convex body (a fuselage, a nacelle, a wing's leading edge) the fit lies
// below the centre's disparity, most near the limbs, where the disparity
// falls steeply: the sensed cloud sits too far from the cameras, the
// registered receiver too far aft (the default pipeline's x bias on ideal
// renders; docs/analysis.md, "The window's bias on curved surfaces").
//
// PredictWindowBias evaluates that fit on the model's own disparity field
// (ModelDisparity: the receiver's mesh rasterized in the rectified left
// camera at a pose) with the images' gradients as weights, and returns fit
// minus the model's disparity at the window's centre: the bias a refined
// disparity carries there. Samples off the model (the background, whose
// disparity the model does not know) get no weight. Subtracting the
// prediction at the registered pose and registering again removes the bias
// to first order; nothing in it comes from truth.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

#include "aar/analyzer/mesh.h"
#include "aar/stereo_calibration.h"

namespace aar {

struct WindowBiasOptions {
  int half_window_px = 4;  ///< the refinement's half window (SubpixelOptions::half_window_px) [px]
  bool slanted = true;     ///< the refinement's window model: affine (true) or one shift
  /// A window with fewer of its samples on the model than this fraction
  /// gets no prediction (0): its fit would rest on a few samples.
  double min_model_fraction = 0.5;
  /// A prediction larger than this is not trusted (0 instead): the pose or
  /// the model is off there [px].
  double max_bias_px = 0.25;

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

/// The model's disparity in the rectified left image over `region` (CV_32F,
/// region-sized; NaN where the model does not cover the pixel centre):
/// d = (Q(2,3) / z - Q(3,3)) / Q(3,2), z the depth of `mesh` at the pose
/// rect_left_from_receiver, rasterized with the rectified camera P1.
cv::Mat ModelDisparity(const TriangleMesh& mesh, const StereoCalibration& calibration,
                       const Eigen::Isometry3d& rect_left_from_receiver, const cv::Rect& region, double near_m);

/// The predicted bias of each refined disparity `pixels[k]` = (u, v, d)
/// (rectified left image; SensedCloud::pixels) [px], 0 where there is no
/// prediction. `rect_left`, `rect_right` (8-bit grey) and `model_disparity`
/// cover the same region, whose top-left is the image pixel `origin`.
std::vector<double> PredictWindowBias(const cv::Mat& rect_left, const cv::Mat& rect_right,
                                      const cv::Mat& model_disparity, cv::Point origin,
                                      const std::vector<Eigen::Vector3d>& pixels, const WindowBiasOptions& options);

}  // namespace aar
