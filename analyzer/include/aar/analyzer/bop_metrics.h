#pragma once
// The 6-DoF object pose community's error functions and scores, for one
// object without symmetries (the receiver), in metres and pixels.
//
// Pose error functions of the BOP benchmark (Hodan et al., "BOP Challenge
// 2020 on 6D Object Localization", ECCV Workshops 2020, section 2.2; the
// bop_toolkit's pose_error.py), with P the true and P' the estimated
// cam_from_model transform and V the model's vertices:
//
//   MSSD = max over x in V of |P' x - P x|                (Maximum Symmetry-Aware Surface Distance)
//   MSPD = max over x in V of |proj(P' x) - proj(P x)|    (Maximum Symmetry-Aware Projection Distance)
//
// (BOP minimises both over the object's symmetries; the receiver has none,
// so the minimum is the identity's). proj is the pinhole camera K (BOP's
// cam_K: fx, fy, cx, cy, no lens distortion). And the older ADD / ADD-S
// (Hinterstoisser et al., ACCV 2012, equations 1-2):
//
//   ADD   = mean over x in V of |P' x - P x|
//   ADD-S = mean over x1 in V of min over x2 in V of |P' x1 - P x2|
//
// Scores over a set of targets (every frame with a truth; a frame without
// an estimate is a miss): BOP's recall at a threshold is the fraction of
// targets whose error is below it, AR_MSSD the mean recall over the
// thresholds 0.05, 0.10, ..., 0.50 of the object's diameter, AR_MSPD over
// 5, 10, ..., 50 px times r = image width / 640 (BOP's normalisation to a
// 640 px wide image). VSD (vsd.h) needs the test image's depth, so it exists
// only for datasets with depth truth: AR_VSD is the mean recall over its 10
// tolerances tau and 10 thresholds theta, and BOP's AR the mean of AR_VSD,
// AR_MSSD and AR_MSPD; `ar_mssd_mspd`, the mean of the last two, exists for
// every run. ADD (ADD-S) recall is the
// fraction of targets with ADD (ADD-S) below 10 % of the diameter. The
// diameter is the largest distance between two vertices (BOP's
// models_info.json).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "aar/analyzer/kdtree.h"
#include "aar/analyzer/mesh.h"
#include "aar/analyzer/vsd.h"
#include "aar/rig.h"

namespace aar {

/// The model as the error functions see it: its distinct vertices, their
/// diameter and a search tree over them (ADD-S).
class BopObject {
 public:
  /// Throws aar::Error when the mesh has fewer than two distinct vertices.
  explicit BopObject(const TriangleMesh& mesh);

  const std::vector<Eigen::Vector3d>& vertices() const { return tree_->points(); }
  double diameter_m() const { return diameter_m_; }
  const KdTree3d& tree() const { return *tree_; }

 private:
  std::unique_ptr<KdTree3d> tree_;
  double diameter_m_ = 0.0;
};

/// The four errors of one estimate.
struct PoseErrorMetrics {
  double mssd_m = 0.0;           ///< maximum surface distance [m]
  double mspd_px = 0.0;          ///< maximum projection distance [px]
  double add_m = 0.0;            ///< mean distance of corresponding vertices [m]
  double adds_m = 0.0;           ///< mean distance to the nearest vertex [m]
  std::optional<VsdErrors> vsd;  ///< e_VSD at each tau (vsd.h), where the frame has depth truth
};

/// The errors of `cam_from_model_estimate` against `cam_from_model_truth`,
/// projected with `camera`'s pinhole part (its distortion ignored, as BOP's
/// cam_K). A vertex behind either pose's camera counts as infinitely far in
/// MSPD.
PoseErrorMetrics ComputePoseErrorMetrics(const BopObject& object, const Intrinsics& camera,
                                         const Eigen::Isometry3d& cam_from_model_estimate,
                                         const Eigen::Isometry3d& cam_from_model_truth);

/// BOP's thresholds: MSSD as fractions of the diameter, MSPD in pixels of a
/// 640 px wide image.
inline constexpr std::array<double, 10> kMssdThresholdFractions = {0.05, 0.10, 0.15, 0.20, 0.25,
                                                                   0.30, 0.35, 0.40, 0.45, 0.50};
inline constexpr std::array<double, 10> kMspdThresholdsPx640 = {5, 10, 15, 20, 25, 30, 35, 40, 45, 50};
/// ADD / ADD-S: correct below this fraction of the diameter.
inline constexpr double kAddThresholdFraction = 0.1;

/// What the scores need to know about the object and the camera.
struct BopScale {
  double diameter_m = 0.0;  ///< BopObject::diameter_m
  int image_width_px = 0;   ///< the camera's image width (MSPD's r = width / 640)
};

struct BopScores {
  size_t targets = 0;         ///< frames scored (with or without an estimate)
  double ar_mssd = 0.0;       ///< mean recall over the MSSD thresholds
  double ar_mspd = 0.0;       ///< mean recall over the MSPD thresholds
  double ar_mssd_mspd = 0.0;  ///< (ar_mssd + ar_mspd) / 2 (BOP's AR without VSD)
  double add_recall = 0.0;    ///< fraction with ADD < 0.1 diameter
  double adds_recall = 0.0;   ///< fraction with ADD-S < 0.1 diameter
  /// Where some target has e_VSD: the mean recall over kVsdTauFractions x
  /// kVsdThresholds (a target without e_VSD is a miss), and BOP's AR, the
  /// mean of ar_vsd, ar_mssd and ar_mspd.
  std::optional<double> ar_vsd;
  std::optional<double> ar;
};

/// Scores of the targets' errors (nullopt: no estimate, a miss at every
/// threshold). All zero for no targets. Throws aar::Error for a scale
/// without a positive diameter and width.
BopScores ScoreBop(const std::vector<std::optional<PoseErrorMetrics>>& errors, const BopScale& scale);

}  // namespace aar
