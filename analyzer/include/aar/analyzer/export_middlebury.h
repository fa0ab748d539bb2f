#pragma once
// Middlebury stereo (2014 layout), one folder per frame, so that a stereo
// matcher can be scored on rendered frames:
//
//   OUT/NNNNNN/im0.png, im1.png   the left and right images (already rectified:
//                                 the ideal calibration's R1 = R2 = I)
//   OUT/NNNNNN/calib.txt          cam0, cam1, doffs, baseline [mm], width, height,
//                                 ndisp, isint, vmin, vmax
//   OUT/NNNNNN/disp0GT.pfm        true disparity of the left view, d = f b / Z
//                                 (Z: the left depth truth), +inf where no surface
//   OUT/NNNNNN/disp1GT.pfm        the same for the right view (datasets with --depth-right)
//
// PFM: "Pf" header, little-endian float32 (scale -1), rows bottom to top.

#include <opencv2/core.hpp>
#include <string>

#include "aar/analyzer/export_source.h"

namespace aar {

/// PFM bytes of a CV_32FC1 image (row 0 = top of the image).
std::string EncodePfm(const cv::Mat& image);

/// Disparity of a depth image: f b / Z where Z > 0, +inf elsewhere [px].
cv::Mat DisparityFromDepth(const cv::Mat& depth_m, double focal_times_baseline_px_m);

ExportResult ExportMiddlebury(const ExportOptions& options);

}  // namespace aar
