#pragma once
// BOP's Visible Surface Discrepancy (Hodan et al., "On Evaluation of 6D
// Object Pose Estimation", ECCV Workshops 2016, section 2.2; as the BOP
// Challenge 2019-2020 scores it, the bop_toolkit's pose_error.vsd with
// visibility.py's "bop19" mode).
//
// With D the test image's depth (0 where nothing was measured), S and S' the
// model rendered at the true and the estimated pose (no surface: not
// rendered), each turned from depth along the optical axis into distance
// from the camera's centre, and delta the visibility tolerance:
//
//   visible(S)  = S rendered and (S <= D + delta or D missing)   (V: the truth's visible part)
//   visible(S') = visible by the same test, or rendered where V is  (V')
//   e_VSD(tau)  = (|{p in V and V' : |S'(p) - S(p)| >= tau}| + |V xor V'|) / |V or V'|
//
// and 1 where V or V' is empty. BOP 2019's parameters: delta 15 mm, tau =
// 0.05, 0.10, ..., 0.50 of the object's diameter; an estimate is correct at
// threshold theta = 0.05, 0.10, ..., 0.50 when e_VSD < theta, and AR_VSD is
// the mean recall over the 100 (tau, theta) pairs (bop_metrics.h, ScoreBop).
// The renderings use the camera's pinhole part (BOP's cam_K); the test depth
// must be a pinhole image of the same camera.

#include <Eigen/Geometry>
#include <array>
#include <opencv2/core.hpp>

#include "aar/analyzer/depth_raster.h"
#include "aar/analyzer/mesh.h"
#include "aar/rig.h"

namespace aar {

inline constexpr double kVsdDeltaM = 0.015;  ///< BOP's visibility tolerance delta [m]
/// BOP's misalignment tolerances tau, as fractions of the object's diameter.
inline constexpr std::array<double, 10> kVsdTauFractions = {0.05, 0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45, 0.50};
/// BOP's correctness thresholds theta on e_VSD.
inline constexpr std::array<double, 10> kVsdThresholds = {0.05, 0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40, 0.45, 0.50};

/// e_VSD at each of kVsdTauFractions.
using VsdErrors = std::array<double, kVsdTauFractions.size()>;

/// e_VSD from the model's depth at the estimate and at the truth
/// (RasterizeDepth: +inf where no surface) and the test image's depth
/// (CV_32F metres along the optical axis, 0 where nothing was measured),
/// all three of `camera`'s size. Throws aar::Error for other sizes or
/// types, or a diameter that is not positive.
VsdErrors VsdFromDepth(const DepthBuffer& estimate, const DepthBuffer& truth, const cv::Mat& test_depth_m,
                       const Intrinsics& camera, double diameter_m, double delta_m = kVsdDeltaM);

/// Renders `mesh` at both poses with RasterizeDepth (clipped at `near_m`)
/// and returns VsdFromDepth.
VsdErrors ComputeVsd(const TriangleMesh& mesh, const Intrinsics& camera,
                     const Eigen::Isometry3d& cam_from_model_estimate, const Eigen::Isometry3d& cam_from_model_truth,
                     const cv::Mat& test_depth_m, double diameter_m, double near_m);

}  // namespace aar
