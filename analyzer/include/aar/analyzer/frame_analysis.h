#pragma once
// The per-frame pipeline (thesis Figure 6, sections 3.4-3.6): read the stereo
// pair, rectify, block-match, re-project into the tanker frame, register the
// reference model with ICP, compare with the sidecar's truth.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "aar/analyzer/boom_mask.h"
#include "aar/analyzer/clipped_pixels.h"
#include "aar/analyzer/direct_stereo.h"
#include "aar/analyzer/disparity.h"
#include "aar/analyzer/disparity_cleaning.h"
#include "aar/analyzer/frame_dump.h"
#include "aar/analyzer/icp.h"
#include "aar/analyzer/plane_icp.h"
#include "aar/analyzer/pose_statistics.h"
#include "aar/analyzer/propeller_mask.h"
#include "aar/analyzer/reference_model.h"
#include "aar/analyzer/reprojection.h"
#include "aar/analyzer/stereo_truth.h"
#include "aar/analyzer/window_bias.h"
#include "aar/opened_dataset.h"
#include "aar/stereo_calibration.h"

namespace aar {

enum class IcpSeed {
  kCentroid,  ///< zero attitude at the sensed cloud's centroid (thesis Experiment 1)
  /// The last frame's estimate (centroid for the first frame, after a
  /// failure, or when that estimate's attitude exceeds max_seed_attitude_deg).
  kPreviousFrame,
};
std::string ToString(IcpSeed seed);
IcpSeed ParseIcpSeed(const std::string& text);

/// Registration algorithm.
enum class Registration {
  kPointToPoint,  ///< IcpRegistration: closed-form point-to-point (thesis 3.6)
  kPointToPlane,  ///< PlaneIcpRegistration: robust, noise-weighted point-to-plane
};
std::string ToString(Registration registration);
Registration ParseRegistration(const std::string& text);

/// Whole-pipeline presets. The struct's defaults are kDefault.
enum class Preset {
  kDefault,  ///< the best pipeline measured (docs/analysis.md)
  kThesis,   ///< Parsons (2017) as closely as its text allows
};
std::string ToString(Preset preset);
Preset ParsePreset(const std::string& text);

struct FrameAnalysisOptions {
  /// Thesis 3.4: BM, 48 disparities, block 9, speckle filter; disparities
  /// <= 0.5 px are background (a textured one: docs/analysis.md).
  DisparityOptions disparity = [] {
    DisparityOptions o;
    o.background_disparity_px = 0.5;
    return o;
  }();
  /// Remove the foreground-fattening halo (disparity_cleaning.h); its radius
  /// is set from the block size (block_size / 2) by ForPreset and the CLI.
  bool remove_halo = true;
  HaloRemovalOptions halo;
  /// Drop the matches whose window reaches a clipped (white) pixel in either
  /// image (clipped_pixels.h: a sun glint, a saturated sensor); its radius
  /// is set like the halo's. Off by default.
  bool remove_clipped = false;
  ClippedPixelOptions clipped;
  /// Subtract MatcherRoundingBiasPx(algorithm) (StereoBM: 15/512 px) from
  /// the matcher's disparities (reprojection.matcher_bias_px), on top of
  /// reprojection.disparity_offset_px.
  bool remove_rounding_bias = true;
  /// Symmetric sub-pixel refinement of every kept disparity (subpixel.h),
  /// with slanted windows by default (subpixel.slanted): it removes the
  /// disparity error that grows with the surface's slope, which tilted the
  /// registered receiver (docs/analysis.md item 5). The thesis preset: off.
  bool refine_subpixel = true;
  SubpixelOptions subpixel;
  /// With refine_subpixel: predict each refined disparity's window bias on
  /// the model at the registered pose, subtract it and register again
  /// (window_bias.h); needs FrameAnalyzer::SetReceiverMesh.
  bool correct_window_bias = false;
  WindowBiasOptions window_bias;
  /// After registration, fit the pose (direct.fit: its translation, by
  /// default) to the rectified images directly (direct_stereo.h): every
  /// pixel the model covers, at the disparity the model has there; needs
  /// FrameAnalyzer::SetReceiverMesh.
  bool refine_direct = false;
  DirectStereoOptions direct;
  /// Re-projection: <= 750 m and <= 1.5 times the cloud's median depth;
  /// about 4000 points (one in eight or more).
  ReprojectionOptions reprojection = [] {
    ReprojectionOptions o;
    o.target_points = 4000;
    o.max_depth_over_median = 1.5;
    return o;
  }();
  Registration registration = Registration::kPointToPlane;
  PlaneIcpOptions plane_icp;  ///< for kPointToPlane
  /// kPointToPlane with a shelled model: pair sensed points with the full
  /// model's surface (PlaneIcpRegistration::SetSensedPairingSurface).
  bool pair_sensed_with_full_surface = true;
  IcpOptions icp;  ///< for kPointToPoint (thesis 3.6: 30 iterations)
  IcpSeed seed = IcpSeed::kCentroid;
  /// kPreviousFrame: a last estimate with |roll|, |pitch| or |yaw| beyond this
  /// does not seed the next frame, which starts from the centroid again
  /// [deg]. A receiver in formation behind the tanker stays within a few
  /// degrees of its attitude (the CONOPS path: 2.8 deg at most); an estimate
  /// beyond 15 deg is a registration gone wrong, and seeding from it would
  /// carry the error on.
  double max_seed_attitude_deg = 15.0;
  /// Tracking (once a frame is measured): rectify and match only the region
  /// where the receiver is predicted (constant velocity from the last two
  /// estimates; the model's box there, grown by track_margin_fraction of its
  /// size and track_margin_px, plus the disparity search to its left); when
  /// the estimate reaches the region's border or the frame fails there, the
  /// whole image is measured instead. Independent of `seed`. Off by default:
  /// results then depend on the frames before, so shards differ from one run.
  bool track_region = false;
  double track_margin_fraction = 0.15;
  int track_margin_px = 16;
  /// Compare the sensed cloud with the depth truth when the dataset has it
  /// (stereo_truth.h); `bench` turns it off to time only the pipeline.
  bool compare_with_truth = true;
  /// When the estimate puts part of the receiver beyond the disparity search
  /// (near frames), match again with the search widened to cover it.
  bool widen_disparity_search = true;
  /// Diagnosis (datasets with --depth): register the ideal cloud, the true
  /// surface points at the sensed pixels, instead of the stereo cloud.
  bool register_truth_cloud = false;
  /// With register_truth_cloud: zero-mean Gaussian disparity noise of this
  /// standard deviation [px] moves each ideal point along its ray (depth
  /// f b / (f b / z + e)), seeded by the frame index: the registration's
  /// response to stereo noise alone, without stereo's other errors.
  double truth_cloud_noise_px = 0.0;
  size_t min_sensed_points = 30;  ///< fewer sensed points: the frame is not measured ("receiver out of view")
  /// Registration failed (ICP did not converge onto the receiver) when its
  /// residual RMS exceeds max_icp_rmse_m + 3 sigma_z, where sigma_z =
  /// r^2 disparity_noise_px / (f b) is the stereo depth noise expected at the
  /// estimated range r (f b from Q); such a frame is recorded as not measured.
  double max_icp_rmse_m = 2.0;  ///< residual allowance at zero range [m]
  /// Registration failed, too, when fewer than this fraction of the sensed
  /// points pair with the model: a cleaned cloud on a registered receiver
  /// pairs nearly all of them (at least 0.92 on every measured CONOPS and
  /// characterization frame), while a seed far from the receiver leaves the
  /// gate no pair and the ICP where it started (its residual over no pairs
  /// is 0). With a seed from the last frame, such a frame is measured again
  /// from the centroid on the whole image (the tracker's safe fallback).
  double min_inlier_fraction = 0.5;
  double disparity_noise_px = 0.1;  ///< disparity noise used for sigma_z [px] (a typical block-matching accuracy)
  /// Remove the boom's pixels before re-projection (boom_mask.h), drawn from
  /// the sidecar's boom angles and the rig; needs FrameAnalyzer::EnableBoomMask.
  /// Off by default (datasets without the boom are unaffected either way).
  bool mask_boom = false;
  BoomMaskOptions boom_mask;
  /// Drop the sensed points inside the receiver's propeller discs under the
  /// registered pose and register again (propeller_mask.h). Off by default:
  /// the thesis's receiver has no propellers.
  bool mask_propellers = false;
  PropellerMaskOptions propeller_mask;

  /// The options of a preset: kDefault = these defaults; kThesis = BM 9/48
  /// with speckle filter, no halo removal, no rounding correction, no
  /// sub-pixel refinement, one point in eight, point-to-point ICP pairing
  /// model points with sensed points, 30 iterations, centroid seed with zero
  /// attitude, no widened search.
  static FrameAnalysisOptions ForPreset(Preset preset);

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

/// The last estimates of a run (flight-path time and pose), for tracking.
struct TrackHistory {
  std::optional<std::pair<double, Pose>> last;         ///< most recent measured frame
  std::optional<std::pair<double, Pose>> before_last;  ///< the one before it
};

/// The ICP seed for the next frame, nullopt for the centroid: with
/// kPreviousFrame, the last estimate itself, not the constant-velocity
/// prediction (extrapolating two noisy estimates doubles their noise; in
/// region A, where the attitude is weakly observed, the extrapolated errors
/// grew from frame to frame, docs/analysis.md step 9), unless its attitude
/// exceeds max_seed_attitude_deg.
std::optional<Pose> SeedFromHistory(const TrackHistory& history, const FrameAnalysisOptions& options);

/// Analyzes frames of one dataset with one calibration and one reference model.
class FrameAnalyzer {
 public:
  /// The model needs normals for kPointToPlane.
  FrameAnalyzer(const StereoCalibration& calibration, const Eigen::Isometry3d& tanker_from_left,
                const ReferenceModel& model, const FrameAnalysisOptions& options,
                const ReferenceModel* full_surface = nullptr);

  /// Removes the boom's pixels of frames whose sidecar has a boom pose
  /// (options.mask_boom); `boom` and `tube` from the dataset's boom.glb and
  /// boom_tube.glb.
  void EnableBoomMask(TriangleMesh boom, TriangleMesh tube);

  /// The receiver's mesh, which the passes that predict the images from the
  /// model need (options.correct_window_bias, options.refine_direct).
  void SetReceiverMesh(TriangleMesh receiver);

  /// Analyzes frame `index` of `dataset`. Never throws for a bad frame: a
  /// missing or corrupt image, a malformed sidecar, a hash mismatch, a
  /// sidecar rendered with other settings than the manifest records
  /// (OpenedDataset::Sidecar), too few sensed points or a failed
  /// registration give a result whose `status` says why. `history` holds the last good estimates (for kPreviousFrame).
  /// With `dump`, also returns the images and clouds of the frame (frame_dump.h);
  /// with `depth_truth`, the left camera's depth truth where the analysis read
  /// it (options.compare_with_truth on a dataset with depth), else nullopt.
  FrameResult Analyze(const OpenedDataset& dataset, size_t index, const TrackHistory& history,
                      FrameDump* dump = nullptr, std::optional<DepthTruth>* depth_truth = nullptr) const;

 private:
  StereoCalibration calibration_;
  Eigen::Isometry3d tanker_from_left_;
  double focal_times_baseline_px_m_;         // f b = Q(2,3) / Q(3,2)
  Eigen::Isometry3d tanker_from_rect_left_;  // tanker_from_left * R1^T
  Rectifier rectifier_;
  std::vector<Eigen::Vector3d> model_points_;
  std::unique_ptr<RegistrationMethod> registration_;  // options.registration's
  FrameAnalysisOptions options_;
  std::unique_ptr<BoomMasker> boom_masker_;
  std::unique_ptr<TriangleMesh> receiver_mesh_;

  RegistrationResult Register(const std::vector<Eigen::Vector3d>& sensed, const std::optional<Pose>& previous) const;
  RegistrationResult RegisterFrom(const std::vector<Eigen::Vector3d>& sensed, const Eigen::Isometry3d& initial) const;
  // options.mask_propellers: registers again without the points in the
  // propeller discs at `icp`'s pose, pass by pass, while the masks agree.
  void MaskPropellersAndRegister(const std::vector<Eigen::Vector3d>& sensed, RegistrationResult& icp) const;
  // options.correct_window_bias: subtracts the window bias predicted at
  // `icp`'s pose from `cloud` and registers again; keeps both only when the
  // new pose passes the jump test. Returns whether it did.
  bool CorrectWindowBias(const cv::Mat& rect_left, const cv::Mat& rect_right, const cv::Rect& region,
                         SensedCloud& cloud, RegistrationResult& icp) const;
  // options.refine_direct: fits `icp`'s pose to the rectified images
  // (direct_stereo.h) and keeps the fit where it applied.
  void RefineDirectly(const cv::Mat& rect_left, const cv::Mat& rect_right, const cv::Rect& region,
                      RegistrationResult& icp) const;
  // One frame's images and what the analysis reads beside them.
  struct FrameInputs {
    cv::Mat left, right;
    std::optional<DepthTruth> truth;  // options.compare_with_truth on a dataset with depth
    std::string left_path;            // for messages
    const BoomMasks* boom = nullptr;  // the boom's pixels to remove (options.mask_boom)
  };
  // Disparities of the rectified `region` with `disparity_options`, the halo
  // and the boom's pixels removed (stage time and dump filled in).
  DisparityMap Match(const cv::Mat& rect_left, const cv::Mat& rect_right, const cv::Rect& region,
                     const DisparityOptions& disparity_options, const BoomMasks* boom, FrameResult& r,
                     FrameDump* dump) const;
  // One region's rectified pair, its refiner (options.refine_subpixel) and
  // the cloud re-projected from its disparities.
  struct SensedRegion;
  // Rectifies, matches and re-projects `region` (stage times and dump filled
  // in); throws aar::Error when fewer than min_sensed_points remain.
  SensedRegion Sense(const FrameInputs& in, const cv::Rect& region, const DisparityOptions& disparity_options,
                     FrameResult& r, FrameDump* dump) const;
  // The cloud against depth truth (r.stereo_truth) and the indices of its
  // points on the propeller blades (`blades`); with
  // options.register_truth_cloud the cloud becomes the ideal one.
  void CompareCloudWithTruth(const DepthTruth& truth, SensedCloud& cloud, FrameResult& r,
                             std::vector<size_t>& blades) const;
  // The depth-truth comparison's options for frame `r` (its true pose).
  StereoTruthOptions TruthOptions(const FrameResult& r) const;
  // How many of the cloud's points on the propeller blades the registration
  // kept: outside the propeller mask's discs at `icp`'s pose, or all of them
  // without the mask.
  size_t PropellersKept(const SensedCloud& cloud, const std::vector<size_t>& blades,
                        const RegistrationResult& icp) const;
  // Rectify, match, re-project and register in `roi` (empty: the whole
  // image), searching `num_disparities` (0: options.disparity's).
  RegistrationResult Measure(const FrameInputs& in, const cv::Rect& roi, int num_disparities,
                             const std::optional<Pose>& seed, FrameResult& r, FrameDump* dump) const;
  // Why a registration failed: its residual beyond what stereo noise at its
  // range explains, or too few pairs (min_inlier_fraction); empty when it did not.
  std::string RegistrationFailure(const RegistrationResult& registered, size_t sensed_points) const;
  // Measures in the region `predicted` puts the receiver in (tracking), or
  // the whole image when there is none or the receiver reaches its border,
  // from `seed`; and again from the centroid over the whole image when a
  // seeded registration fails. `why` says why the last one failed (empty: it did not).
  RegistrationResult MeasureFrame(const FrameInputs& in, const std::optional<Pose>& predicted,
                                  const std::optional<Pose>& seed, FrameResult& r, FrameDump* dump,
                                  std::string& why) const;
  // The model's box in the rectified left image at a pose, grown by margins.
  cv::Rect PredictedRegion(const Eigen::Isometry3d& tanker_from_receiver, double margin_fraction, int margin_px) const;
  cv::Rect PredictedRegion(const Eigen::Isometry3d& tanker_from_receiver) const {
    return PredictedRegion(tanker_from_receiver, options_.track_margin_fraction, options_.track_margin_px);
  }
  // The disparities to search for a receiver that needs `needed_px` at its
  // nearest point: 10 % and 2 px more, in StereoBM's steps of 16 (at least 16).
  int DisparitiesFor(double needed_px) const;
  // Largest disparity the model needs at a pose (its nearest point) [px].
  double ModelMaxDisparityPx(const Eigen::Isometry3d& tanker_from_receiver) const;
};

}  // namespace aar
