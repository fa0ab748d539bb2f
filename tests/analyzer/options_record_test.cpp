// run.json's options read back (options_record.h): every record OptionsJson
// writes reads back to options that write the same record, and a bad record
// names the key.

#include "aar/analyzer/options_record.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "../test_support.h"
#include "aar/error.h"

namespace aar {
namespace {

using test::ErrorOf;

AnalysisRunOptions WithPreset(Preset preset) {
  AnalysisRunOptions o;
  o.preset = preset;
  o.frame = FrameAnalysisOptions::ForPreset(preset);
  return o;
}

TEST(OptionsRecord, EveryRecordReadsBackToTheSameRecord) {
  std::vector<std::pair<std::string, std::function<void(AnalysisRunOptions&)>>> cases = {
      {"default", [](AnalysisRunOptions&) {}},
      {"thesis", [](AnalysisRunOptions& o) { o = WithPreset(Preset::kThesis); }},
      {"tracking, every optional stage",
       [](AnalysisRunOptions& o) {
         FrameAnalysisOptions& f = o.frame;
         f.seed = IcpSeed::kPreviousFrame;
         f.max_seed_attitude_deg = 9.0;
         f.track_region = true;
         f.track_margin_px = 20;
         f.correct_window_bias = true;
         f.window_bias.max_bias_px = 0.2;
         f.refine_direct = true;
         f.direct.fit = DirectStereoFit::kPose;
         f.direct.max_motion_px = 8.0;
         f.mask_boom = true;
         f.boom_mask.margin_px = 9;
         f.mask_propellers = true;
         f.propeller_mask.passes = 2;
         f.remove_clipped = true;
         f.clipped.radius_px = 6;
         f.register_truth_cloud = true;
         f.truth_cloud_noise_px = 0.12;
         f.subpixel.interpolation = SubpixelInterpolation::kCubicBSpline;
         f.subpixel.prefilter_sigma_px = 0.6;
         f.plane_icp.pairing = PlanePairing::kSymmetric;
         f.plane_icp.max_correspondence_distance_m = std::numeric_limits<double>::infinity();
         f.min_sensed_points = 50;
         o.filter.window_s = 0.25;
         o.reference.model = "full";
         o.reference.options.raster_width_px = 3000;
         o.reference.options.tanker_from_receiver = Pose{{30.0, 1.0, 5.0}, 1.0, 2.0, 3.0};
       }},
      {"point-to-point, no halo, no refinement",
       [](AnalysisRunOptions& o) {
         o.frame.registration = Registration::kPointToPoint;
         o.frame.icp.correspondence = IcpCorrespondence::kSensedToModel;
         o.frame.icp.max_correspondence_distance_m = 3.0;
         o.frame.remove_halo = false;
         o.frame.refine_subpixel = false;
         o.frame.disparity.algorithm = DisparityAlgorithm::kSemiGlobal;
       }},
  };
  for (const auto& [name, edit] : cases) {
    SCOPED_TRACE(name);
    AnalysisRunOptions written;
    edit(written);
    const nlohmann::json record = OptionsJson(written);
    AnalysisRunOptions read;  // from other options entirely
    read = WithPreset(written.preset == Preset::kThesis ? Preset::kDefault : Preset::kThesis);
    read.frame.refine_direct = true;
    ApplyRecordedOptions(record, "run.json", read);
    EXPECT_EQ(OptionsJson(read).dump(), record.dump());
    EXPECT_EQ(read.mask_boom, written.frame.mask_boom);
    EXPECT_EQ(read.mask_propellers, written.frame.mask_propellers);
  }
}

TEST(OptionsRecord, BadRecordsNameTheKey) {
  const nlohmann::json good = OptionsJson(AnalysisRunOptions{});
  const std::vector<std::tuple<std::string, std::function<void(nlohmann::json&)>, std::string>> cases = {
      {"missing section", [](nlohmann::json& j) { j.erase("icp"); }, "run.json: options.icp: missing"},
      {"missing key", [](nlohmann::json& j) { j["disparity"].erase("block_size"); },
       "options.disparity.block_size: missing"},
      {"wrong type", [](nlohmann::json& j) { j["reprojection"]["keep_one_in"] = "eight"; },
       "options.reprojection.keep_one_in: malformed"},
      {"unknown pairing", [](nlohmann::json& j) { j["icp"]["pairing"] = "nearest"; }, "options.icp.pairing: "},
      {"unknown preset", [](nlohmann::json& j) { j["preset"] = "fast"; }, "options.preset: "},
      {"invalid value", [](nlohmann::json& j) { j["disparity"]["block_size"] = 4; }, "run.json: options: "},
  };
  for (const auto& [name, edit, message] : cases) {
    SCOPED_TRACE(name);
    nlohmann::json record = good;
    edit(record);
    AnalysisRunOptions options;
    const std::string error = ErrorOf([&] { ApplyRecordedOptions(record, "run.json", options); });
    EXPECT_NE(error.find(message), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace aar
