// FrameAnalysisOptions: the presets, their check, and the names of their
// enumerations on the command line and in run.json (frame_analysis.h).

#include <cmath>
#include <optional>
#include <string>

#include "aar/analyzer/frame_analysis.h"
#include "aar/error.h"
#include "aar/text.h"

namespace aar {

std::string ToString(IcpSeed seed) { return seed == IcpSeed::kCentroid ? "centroid" : "previous"; }

IcpSeed ParseIcpSeed(const std::string& text) {
  if (text == "centroid") return IcpSeed::kCentroid;
  if (text == "previous") return IcpSeed::kPreviousFrame;
  throw Error("--seed '" + text + "': expected centroid or previous");
}

std::optional<Pose> SeedFromHistory(const TrackHistory& history, const FrameAnalysisOptions& options) {
  if (options.seed != IcpSeed::kPreviousFrame || !history.last) return std::nullopt;
  const Pose& last = history.last->second;
  const double limit = options.max_seed_attitude_deg;
  if (!(std::abs(last.roll_deg) <= limit && std::abs(last.pitch_deg) <= limit && std::abs(last.yaw_deg) <= limit)) {
    return std::nullopt;
  }
  return last;
}

std::string ToString(Registration registration) {
  return registration == Registration::kPointToPoint ? "point_to_point" : "point_to_plane";
}

Registration ParseRegistration(const std::string& text) {
  if (text == "point_to_point") return Registration::kPointToPoint;
  if (text == "point_to_plane") return Registration::kPointToPlane;
  throw Error("--registration '" + text + "': expected point_to_point or point_to_plane");
}

std::string ToString(Preset preset) { return preset == Preset::kThesis ? "thesis" : "default"; }

Preset ParsePreset(const std::string& text) {
  if (text == "default") return Preset::kDefault;
  if (text == "thesis") return Preset::kThesis;
  throw Error("--preset '" + text + "': expected default or thesis");
}

FrameAnalysisOptions FrameAnalysisOptions::ForPreset(Preset preset) {
  FrameAnalysisOptions o;
  o.halo.radius_px = HaloRadiusPx(o.disparity);
  o.clipped.radius_px = HaloRadiusPx(o.disparity);
  if (preset == Preset::kThesis) {
    o.remove_halo = false;
    o.remove_rounding_bias = false;
    o.refine_subpixel = false;
    o.reprojection.target_points = 0;
    o.reprojection.keep_one_in = 8;
    o.disparity.background_disparity_px = -1.0;  // the thesis keeps every disparity ...
    o.reprojection.max_depth_over_median = 0.0;  // ... and every point up to 750 m
    o.registration = Registration::kPointToPoint;
    o.icp.correspondence = IcpCorrespondence::kModelToSensed;
    o.icp.max_iterations = 30;
    o.seed = IcpSeed::kCentroid;
    o.widen_disparity_search = false;
  }
  return o;
}

void FrameAnalysisOptions::Check() const {
  disparity.Check();
  halo.Check();
  clipped.Check();
  subpixel.Check();
  icp.Check();
  plane_icp.Check();
  boom_mask.Check();
  propeller_mask.Check();
  window_bias.Check();
  direct.Check();
  if (!(truth_cloud_noise_px >= 0.0 && truth_cloud_noise_px <= 10.0))
    throw Error("--truth-cloud-noise must be in [0, 10] px");
  if (truth_cloud_noise_px > 0.0 && !register_truth_cloud) throw Error("--truth-cloud-noise needs --truth-cloud");
  if (reprojection.keep_one_in == 0) throw Error("reprojection keep_one_in must be at least 1");
  if (!(max_icp_rmse_m > 0)) throw Error("max_icp_rmse_m must be positive");
  if (!(min_inlier_fraction >= 0.0 && min_inlier_fraction <= 1.0)) {
    throw Error("min_inlier_fraction must be in [0, 1]");
  }
  if (!(disparity_noise_px > 0.0 && disparity_noise_px <= 100.0)) {
    throw Error("--disparity-noise " + FormatFixed(disparity_noise_px, 3) + ": expected (0, 100] px");
  }
  if (!(std::abs(reprojection.disparity_offset_px) < disparity.num_disparities)) {
    throw Error("--disparity-offset " + FormatFixed(reprojection.disparity_offset_px, 3) +
                ": expected a finite offset smaller than --num-disparities (" +
                std::to_string(disparity.num_disparities) + ")");
  }
  if (!(max_seed_attitude_deg >= 0.0 && max_seed_attitude_deg <= 180.0)) {
    throw Error("max_seed_attitude_deg must be in [0, 180]");
  }
}

}  // namespace aar
