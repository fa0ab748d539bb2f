#include "aar/analyzer/frame_analysis.h"

#include <chrono>
#include <cmath>

#include <opencv2/imgcodecs.hpp>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/region.h"
#include "aar/text.h"

namespace aar {
namespace {

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Reads one image of the pair, checking its hash against the sidecar and the manifest.
cv::Mat ReadImage(const std::filesystem::path& dataset, const FileRef& ref,
                  const std::map<std::string, std::string>& expected_hashes) {
  const std::filesystem::path path = dataset / ref.path;
  if (!std::filesystem::is_regular_file(path)) throw Error(path.string() + ": image missing");
  const std::string bytes = ReadFileBytes(path);
  const std::string hash = Sha256Hex(bytes);
  if (hash != ref.sha256) throw Error(path.string() + ": SHA-256 differs from the sidecar's (file changed or truncated)");
  if (const auto it = expected_hashes.find(ref.path); it != expected_hashes.end() && it->second != hash) {
    throw Error(path.string() + ": SHA-256 differs from manifest.json's");
  }
  const cv::Mat image = cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data())),
                                     cv::IMREAD_COLOR);
  if (image.empty()) throw Error(path.string() + ": cannot decode image");
  return image;
}

}  // namespace

std::string ToString(IcpSeed seed) { return seed == IcpSeed::kCentroid ? "centroid" : "previous"; }

IcpSeed ParseIcpSeed(const std::string& text) {
  if (text == "centroid") return IcpSeed::kCentroid;
  if (text == "previous") return IcpSeed::kPreviousFrame;
  throw Error("--seed '" + text + "': expected centroid or previous");
}

void FrameAnalysisOptions::Check() const {
  std::string reason;
  if (!disparity.IsValid(&reason)) throw Error("disparity options: " + reason);
  icp.Check();
  if (reprojection.keep_one_in == 0) throw Error("reprojection keep_one_in must be at least 1");
  if (!(max_icp_rmse_m > 0)) throw Error("max_icp_rmse_m must be positive");
  if (!(disparity_noise_px >= 0)) throw Error("disparity_noise_px must not be negative");
}

FrameAnalyzer::FrameAnalyzer(const StereoCalibration& calibration, const Eigen::Isometry3d& tanker_from_left,
                             std::vector<Eigen::Vector3d> model_points_in_receiver,
                             const FrameAnalysisOptions& options)
    : calibration_(calibration),
      tanker_from_left_(tanker_from_left),
      focal_times_baseline_px_m_(std::abs(calibration.Q.at<double>(2, 3) / calibration.Q.at<double>(3, 2))),
      rectifier_(calibration),
      registration_(std::move(model_points_in_receiver), options.icp),
      options_(options) {
  options_.Check();
}

FrameResult FrameAnalyzer::Analyze(const std::filesystem::path& dataset, size_t index,
                                   const std::map<std::string, std::string>& expected_hashes,
                                   const std::optional<Pose>& previous) const {
  const auto frame_start = std::chrono::steady_clock::now();
  FrameResult r;
  r.frame = index;
  try {
    auto start = std::chrono::steady_clock::now();
    const std::filesystem::path sidecar_path = SidecarPath(dataset, "frame", index);
    const FrameSidecar sidecar = ReadSidecar(sidecar_path);
    r.time_s = sidecar.time_s;
    r.truth = sidecar.tanker_from_target;
    r.range_m = sidecar.range_m;
    r.region = RegionForRange(sidecar.range_m);
    const std::string relative_sidecar = std::filesystem::relative(sidecar_path, dataset).generic_string();
    if (const auto it = expected_hashes.find(relative_sidecar);
        it != expected_hashes.end() && it->second != Sha256File(sidecar_path)) {
      throw Error(sidecar_path.string() + ": SHA-256 differs from manifest.json's");
    }
    const cv::Mat left = ReadImage(dataset, sidecar.files.at("left"), expected_hashes);
    const cv::Mat right = ReadImage(dataset, sidecar.files.at("right"), expected_hashes);
    if (left.size() != rectifier_.image_size() || right.size() != rectifier_.image_size()) {
      throw Error((dataset / sidecar.files.at("left").path).string() + ": image size differs from the calibration's");
    }
    r.times.load_ms = MillisecondsSince(start);

    start = std::chrono::steady_clock::now();
    cv::Mat rect_left, rect_right;
    rectifier_.Rectify(left, right, rect_left, rect_right);
    r.times.rectify_ms = MillisecondsSince(start);

    start = std::chrono::steady_clock::now();
    const DisparityMap disparity = ComputeDisparity(rect_left, rect_right, options_.disparity);
    r.times.disparity_ms = MillisecondsSince(start);

    start = std::chrono::steady_clock::now();
    const SensedCloud cloud = Reproject(disparity.disparity16, disparity.invalid_value16, calibration_,
                                        tanker_from_left_, options_.reprojection);
    r.sensed_points = cloud.points_in_tanker.size();
    r.times.reproject_ms = MillisecondsSince(start);
    if (cloud.points_in_tanker.size() < options_.min_sensed_points) {
      throw Error((dataset / sidecar.files.at("left").path).string() + ": only " +
                  std::to_string(cloud.points_in_tanker.size()) + " sensed points (receiver out of view?)");
    }

    start = std::chrono::steady_clock::now();
    const Eigen::Isometry3d initial =
        options_.seed == IcpSeed::kPreviousFrame && previous
            ? IsometryFromPose(*previous)
            : InitialGuessAtCentroid(cloud.points_in_tanker, registration_.model_points_in_receiver());
    const IcpResult icp = registration_.Register(cloud.points_in_tanker, initial);
    r.times.icp_ms = MillisecondsSince(start);
    r.icp_iterations = icp.iterations;
    r.icp_converged = icp.converged;
    r.icp_rmse_m = icp.rmse_m;
    r.icp_inliers = icp.num_inliers;
    const double range_m = (icp.tanker_from_receiver.translation() - tanker_from_left_.translation()).norm();
    const double sigma_z = range_m * range_m * options_.disparity_noise_px / focal_times_baseline_px_m_;
    const double limit_m = options_.max_icp_rmse_m + 3.0 * sigma_z;
    if (!icp.tanker_from_receiver.matrix().allFinite() || !(icp.rmse_m <= limit_m)) {
      throw Error((dataset / sidecar.files.at("left").path).string() + ": ICP did not converge (residual " +
                  FormatFixed(icp.rmse_m, 3) + " m, limit " + FormatFixed(limit_m, 3) + " m at " +
                  FormatFixed(range_m, 1) + " m)");
    }
    r.estimate = PoseFromIsometry(icp.tanker_from_receiver);
    r.error = PoseError(r.estimate, r.truth);
    r.status = "ok";
  } catch (const std::exception& e) {  // aar::Error, json or OpenCV errors: the frame is not measured
    r.status = e.what();
  }
  r.times.total_ms = MillisecondsSince(frame_start);
  return r;
}

}  // namespace aar
