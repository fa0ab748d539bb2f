#pragma once
// Removing the tanker's boom from the stereo match (docs/analysis.md,
// "The boom"). The tanker knows its boom's angles and
// extension (the sidecar's `boom`, its own telemetry), the boom's shape (the
// dataset's boom.glb and boom_tube.glb) and its rig, so it can draw where the
// boom is in each rectified image without looking at them: the boom's
// triangles are projected with the calibration's P1 and P2, filled, and grown
// by a margin. Disparities on those pixels, or whose match lies on them in
// the right image, are removed before re-projection. No truth is used.

#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>

#include "aar/analyzer/mesh.h"
#include "aar/boom.h"
#include "aar/stereo_calibration.h"

namespace aar {

struct BoomMaskOptions {
  /// The projected boom is grown by this many pixels: half the 9 px block
  /// (a block straddling the boom's edge is matched on the boom) plus 2 px
  /// for the calibration's and the telemetry's errors [px].
  int margin_px = 6;
  /// Triangles are clipped at this depth in front of the rectified camera [m].
  double near_m = 0.05;

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

/// The boom drawn into the rectified images.
struct BoomMasks {
  cv::Mat1b left;   ///< 255 where the grown boom covers the rectified left image
  cv::Mat1b right;  ///< the same for the rectified right image
};

class BoomMasker {
 public:
  /// `boom` in the boom frame, `tube` in the telescoping tube's (boom.h);
  /// `tanker_from_rect_left` the rectified left camera in the tanker frame.
  BoomMasker(TriangleMesh boom, TriangleMesh tube, const StereoCalibration& calibration,
             const Eigen::Isometry3d& tanker_from_rect_left, const BoomMaskOptions& options = {});

  /// The masks at the boom's pose.
  BoomMasks Draw(const BoomPose& pose) const;

  /// Invalidates the disparities (CV_16S, disparity * 16, `invalid16` where
  /// none) of the rectified left image's region at `region_tl` that lie on
  /// the left mask or whose match (u - d) lies on the right mask. Returns the
  /// number removed.
  static size_t RemoveDisparities(cv::Mat& disparity16, int invalid16, const cv::Point& region_tl,
                                  const BoomMasks& masks);

 private:
  void Fill(const TriangleMesh& mesh, const Eigen::Isometry3d& rect_from_object, bool right, cv::Mat1b& out) const;

  TriangleMesh boom_, tube_;
  Eigen::Isometry3d rect_left_from_tanker_;
  double f_, fy_, cx_, cy_, right_tx_;  // P1 (and P2's f * -b)
  cv::Size size_;
  BoomMaskOptions options_;
};

/// The fraction of the receiver's pixels the boom hides: pixels of the
/// receiver's silhouette (the receiver alone, nonzero) whose object id in
/// the scene's mask is the boom's, over all silhouette pixels (0 when the
/// silhouette is empty). Truth images, for reporting only.
double ReceiverOccludedFraction(const cv::Mat& mask, const cv::Mat& silhouette);

}  // namespace aar
