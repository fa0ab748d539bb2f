#pragma once
// The per-frame pipeline (thesis Figure 6, sections 3.4-3.6): read the stereo
// pair, rectify, block-match, re-project into the tanker frame, register the
// reference model with ICP, compare with the sidecar's truth.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "aar/analyzer/disparity.h"
#include "aar/analyzer/icp.h"
#include "aar/analyzer/pose_statistics.h"
#include "aar/analyzer/reprojection.h"
#include "aar/dataset.h"
#include "aar/stereo_calibration.h"

namespace aar {

enum class IcpSeed {
  kCentroid,       ///< zero attitude at the sensed cloud's centroid (thesis Experiment 1)
  kPreviousFrame,  ///< the previous frame's estimate (centroid for the first frame or after a failure)
};
std::string ToString(IcpSeed seed);
IcpSeed ParseIcpSeed(const std::string& text);

struct FrameAnalysisOptions {
  DisparityOptions disparity;      ///< thesis 3.4: BM, 48 disparities, block 9, speckle filter
  ReprojectionOptions reprojection;  ///< thesis 3.5: <= 750 m, one point in eight
  /// Thesis 3.6: point-to-point, 30 iterations; pairs each sensed point with
  /// its nearest model point (on the CONOPS contact frames this gives 8 cm of
  /// x error where the other direction gives 36 cm, docs/performance.md).
  IcpOptions icp = [] {
    IcpOptions o;
    o.correspondence = IcpCorrespondence::kSensedToModel;
    return o;
  }();
  IcpSeed seed = IcpSeed::kCentroid;
  size_t min_sensed_points = 30;   ///< fewer sensed points: the frame is not measured ("receiver out of view")
  /// Registration failed (ICP did not converge onto the receiver) when its
  /// residual RMS exceeds max_icp_rmse_m + 3 sigma_z, where sigma_z =
  /// r^2 disparity_noise_px / (f b) is the stereo depth noise expected at the
  /// estimated range r (f b from Q); such a frame is recorded as not measured.
  double max_icp_rmse_m = 2.0;        ///< residual allowance at zero range [m]
  double disparity_noise_px = 0.1;    ///< disparity noise used for sigma_z [px] (measured BM RMS 0.12 px)

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

/// Analyzes frames of one dataset with one calibration and one reference model.
class FrameAnalyzer {
 public:
  FrameAnalyzer(const StereoCalibration& calibration, const Eigen::Isometry3d& tanker_from_left,
                std::vector<Eigen::Vector3d> model_points_in_receiver, const FrameAnalysisOptions& options);

  /// Analyzes frame `index` of `dataset`. Never throws for a bad frame: a
  /// missing or corrupt image, a malformed sidecar, a hash mismatch against
  /// `expected_hashes` (relative path -> SHA-256, e.g. the manifest's files),
  /// too few sensed points or a failed registration give a result whose
  /// `status` says why. `previous` is the last good estimate (for kPreviousFrame).
  FrameResult Analyze(const std::filesystem::path& dataset, size_t index,
                      const std::map<std::string, std::string>& expected_hashes,
                      const std::optional<Pose>& previous) const;

 private:
  StereoCalibration calibration_;
  Eigen::Isometry3d tanker_from_left_;
  double focal_times_baseline_px_m_;  // f b = Q(2,3) / Q(3,2)
  Rectifier rectifier_;
  IcpRegistration registration_;
  FrameAnalysisOptions options_;
};

}  // namespace aar
