#pragma once
// Robust, noise-weighted point-to-plane ICP (Chen and Medioni 1992; Low 2004)
// estimating tanker_from_receiver from a sensed stereo cloud (tanker frame)
// and a reference model with surface normals (receiver frame).
//
// Each iteration pairs points with their nearest neighbour (KD-tree, cached
// across iterations), and takes one Gauss-Newton step on
//
//   E = sum_i rho(r_i^2 / sigma_i^2),  r_i = n_i . (tanker_from_receiver * m_i - s_i)
//
// where n_i is the model normal (rotated into the tanker frame), rho is the
// Cauchy kernel with scale robust_scale (in sigmas) and sigma_i is the
// expected standard deviation of r_i under the stereo noise model: a point
// re-projected from disparity d at depth z errs along its viewing ray u_i by
// about z |s_i - c| sigma_d / (f b) (depth noise grows with range squared),
// and across it by z sigma_px / f, so
//
//   sigma_i^2 = sigma_0^2 + (n_i . u_i)^2 sigma_ray^2 + (1 - (n_i . u_i)^2) sigma_lat^2.
//
// Surfaces seen face-on thus count less than surfaces whose normal is across
// the ray, and a long-range cloud stretched along the rays cannot tilt the
// estimate. The step is solved in a frame centred on the sensed centroid
// (well-conditioned 6x6 normal equations, Eigen LDLT). Pairing is from the
// sensed points to the model (a sensed point always has a model surface), or
// both ways (each model point also pulls towards its nearest sensed point,
// which constrains the extent of the receiver along the rays; those pulls
// grow with the paired point's depth noise, model_pull_scale_m), or in the
// noise metric (kMahalanobis): a point re-projected at long range errs along
// its ray by metres and across it by centimetres, so its nearest model point
// in metres is usually not where it came from, and such pairs tilt the model
// towards the rays (the long-range pitch bias). The metric pairing takes the
// model point facing the left camera that is nearest in the camera's
// disparity space scaled by the noise,
//
//   (f x/z / sigma_px, f y/z / sigma_px, f b/z / sigma_d),
//
// where the stereo noise is isotropic (an image-position error across the
// ray, a disparity error along it): the most likely source of the sensed
// point along its own ray. One search grid (sheet_grid.h) per frame over the
// camera-facing model points mapped so, rebuilt when the estimate has turned
// the rays through the receiver by more than sigma_lat / sigma_ray (median
// over the cloud); no model-to-sensed pairs. Iterations stop when a step moves less than both
// tolerances (kMahalanobis also: when the step is small against the
// estimate's own uncertainty, converged_chi2).
//
// The residual above is in metres (kMetric); kDisparity measures each sensed
// point along its own ray instead, in disparity, with the lever arm and the
// variances taken from the model (PlaneResidual; docs/analysis.md item 8).
//
// Single-threaded, fixed summation order: bitwise repeatable.

#include <Eigen/Geometry>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "aar/analyzer/kdtree.h"
#include "aar/analyzer/registration.h"

namespace aar {

enum class PlanePairing {
  kSensedToModel,  ///< each sensed point with its nearest model point
  kSymmetric,      ///< sensed-to-model pairs plus model-to-sensed pairs
  /// Each sensed point with the model point facing the cameras that is
  /// nearest in the stereo noise metric: the most likely source of the
  /// point, not the nearest in metres (see PlaneIcpRegistration::Register).
  kMahalanobis,
};
/// What a sensed-to-model pair's residual measures (model-to-sensed pairs are always kMetric).
enum class PlaneResidual {
  /// n . (p - s) in metres, variance from the sensed point's depth.
  kMetric,
  /// Along the sensed point's own ray, in disparity: the model's tangent plane
  /// predicts the disparity where the ray meets it, minus the measured one;
  /// the rotation's lever arm is that meeting point (see AddDisparity in plane_icp.cpp).
  kDisparity,
  /// n . (p - s) in metres as kMetric, with the rotation's lever arm where the
  /// sensed point's ray meets the model's tangent plane (p, n) instead of the
  /// sensed point itself: the same point for a point on the surface, without
  /// the sensed point's depth noise (no errors in the variables). Where the
  /// ray grazes the plane (|n . u| < 0.1) the sensed point.
  kMetricRay,
};
/// "metric" / "disparity" / "metric-ray"; the parser throws aar::Error on other text.
std::string ToString(PlaneResidual residual);
PlaneResidual ParsePlaneResidual(const std::string& text);

/// "sensed_to_model" / "symmetric" / "mahalanobis"; the parser throws aar::Error on other text.
std::string ToString(PlanePairing pairing);
PlanePairing ParsePlanePairing(const std::string& text);

struct PlaneIcpOptions {
  int max_iterations = 60;  ///< Gauss-Newton steps at most
  /// Converged when a step moves less than this [m] and turns less than
  /// rotation_tolerance_rad: far below the errors of interest (1 mm, 0.001
  /// deg), above the jitter of switching nearest neighbours.
  double translation_tolerance_m = 1e-3;
  double rotation_tolerance_rad = 1e-4;  ///< [rad]
  /// kMahalanobis by default: on the ideal cloud (depth truth at the sensed
  /// pixels) it is 3-14x closer to the truth than kSymmetric in regions A and
  /// B (docs/performance.md, "Pairing in the stereo noise metric").
  PlanePairing pairing = PlanePairing::kMahalanobis;
  PlaneResidual residual = PlaneResidual::kMetric;
  /// kMahalanobis: also converged when a step's squared length under the
  /// estimate's own information matrix (the Gauss-Newton H, weighted by
  /// 1 / sigma^2) is below this, i.e. the step is under sqrt(0.1) = 0.32
  /// standard deviations of the estimate: its pairs keep switching between
  /// model samples by less than the noise allows to resolve [chi^2].
  double converged_chi2 = 0.1;
  /// Pairs farther apart than the larger of this and gate_sigmas times the
  /// sensed point's along-ray sigma are ignored [m] (the gate grows with the
  /// depth noise, so far clouds are not cut); the robust kernel handles the rest.
  double max_correspondence_distance_m = 2.0;
  double gate_sigmas = 3.0;  ///< [sigmas]
  /// Symmetric pairing: scale the model-to-sensed pairs by sensed / model
  /// points, so that each direction weighs the same in total.
  bool balance_directions = false;
  /// Symmetric pairing: at most this many model points query the sensed
  /// cloud per iteration (every k-th, weighted k); 0 = all.
  size_t max_model_queries = 4000;
  /// Symmetric pairing: a model-to-sensed pair counts
  /// sigma_ray^2 / (sigma_ray^2 + t^2) of its weight, t = this [m] (0: all of
  /// it): little where the cloud's depth noise is small against the scale of
  /// the receiver's surface separations (C-12 fuselage half-width 0.73 m,
  /// wing and tail thicknesses 0.1-0.35 m; t = 0.5 m lies between them) and
  /// the sensed-to-model pairs alone are the better estimate, most where the
  /// noise makes those pairs ambiguous and the model's pull holds the
  /// receiver's extent (docs/analysis.md measures both ends).
  double model_pull_scale_m = 0.5;
  /// Coarse-to-fine: iterate on every k-th point of both clouds until the
  /// steps are below ten times the tolerances, then on all; 1 = off.
  size_t coarse_stride = 8;
  size_t coarse_min_points = 250;  ///< the coarse phase keeps at least this many sensed points (far clouds: none)
  double robust_scale = 2.0;       ///< Cauchy kernel scale [sigmas]
  /// kMetric residual, sensed-to-model pairs (not kSymmetric): after
  /// convergence, one Gauss-Newton step that removes the first-order bias
  /// the sensed points' noise gives the rotation. The exact Jacobian's lever
  /// arm is the noisy point itself, so the expected cost holds the noise's
  /// own term, sigma_ray^2 (n.u)^2 + sigma_lat^2 (1 - (n.u)^2) per pair,
  /// which a rotation lowers by turning the model's normals away from the
  /// rays (u); the step is -H^-1 times that term's gradient,
  /// sum w (sigma_ray^2 - sigma_lat^2) (n.u) (u x n) in the rotation's rows,
  /// with the noise model's variances scaled by the pairs' own: the median
  /// of r^2 / sigma^2 over the pairs divided by 0.4549 (the median of a
  /// chi-square with one degree of freedom), so that the step follows the
  /// noise the frame has, not the model's assumed sigma_d.
  bool noise_bias_correction = false;
  // Stereo noise model (see above).
  double disparity_noise_px = 0.1;  ///< sigma_d: disparity noise [px]
  double lateral_noise_px = 0.5;    ///< sigma_px: image-position noise [px]
  double surface_noise_m = 0.005;   ///< sigma_0: model sampling and flat-triangle error [m]
  int kdtree_leaf_size = 10;        ///< nanoflann leaf size [points]

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

/// The stereo rig as the noise model needs it.
struct StereoNoiseGeometry {
  Eigen::Vector3d camera_centre_in_tanker = Eigen::Vector3d::Zero();  ///< left camera centre [m]
  Eigen::Vector3d optical_axis_in_tanker = Eigen::Vector3d::UnitX();  ///< left camera +z (unit)
  double focal_px = 900.0;                                            ///< f [px]
  double focal_times_baseline_px_m = 450.0;                           ///< f b [px m]
};

/// Point-to-plane ICP against one reference model, reusable across frames.
class PlaneIcpRegistration : public RegistrationMethod {
 public:
  /// `model_normals_in_receiver`: one unit normal per model point.
  PlaneIcpRegistration(std::vector<Eigen::Vector3d> model_points_in_receiver,
                       std::vector<Eigen::Vector3d> model_normals_in_receiver, const StereoNoiseGeometry& geometry,
                       const PlaneIcpOptions& options = {});
  ~PlaneIcpRegistration() override;

  /// Pairs sensed points with this surface (points and unit normals, receiver
  /// frame) instead of the model; model-to-sensed pairs keep the model. With
  /// the full model here and the shell as the model, every sensed point finds
  /// the surface it lies on, and only surfaces the cameras see pull the cloud.
  void SetSensedPairingSurface(std::vector<Eigen::Vector3d> points_in_receiver,
                               std::vector<Eigen::Vector3d> normals_in_receiver);

  /// Registers one frame. Throws aar::Error when the sensed cloud is empty or not finite.
  RegistrationResult Register(const std::vector<Eigen::Vector3d>& sensed_points_in_tanker,
                              const Eigen::Isometry3d& initial_tanker_from_receiver) const override;

  const std::vector<Eigen::Vector3d>& model_points_in_receiver() const override { return model_; }

 private:
  std::vector<Eigen::Vector3d> model_;
  std::vector<Eigen::Vector3d> normals_;
  StereoNoiseGeometry geometry_;
  PlaneIcpOptions options_;
  std::unique_ptr<KdTree3d> model_tree_;
  std::vector<Eigen::Vector3d> surface_, surface_normals_;  // empty: the model
  std::unique_ptr<KdTree3d> surface_tree_;
};

}  // namespace aar
