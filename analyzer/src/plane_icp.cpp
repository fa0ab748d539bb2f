#include "aar/analyzer/plane_icp.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <tuple>

#include "aar/analyzer/nearest_cache.h"
#include "aar/analyzer/sheet_grid.h"
#include "aar/error.h"
#include "aar/text.h"
#include "plane_icp_terms.h"

namespace aar {
namespace {

using plane_icp_detail::NoiseAt;
using plane_icp_detail::NoiseOf;
using plane_icp_detail::NormalEquations;
using plane_icp_detail::RayLever;
using plane_icp_detail::SensedNoise;
using plane_icp_detail::UpperMedian;

// The sensed-to-surface search of kMahalanobis. A point's stereo noise is
// isotropic in the left camera's scaled disparity space
//   (f x / z / sigma_px, f y / z / sigma_px, f b / z / sigma_d)
// (image position and disparity, each over its noise; a depth error is a
// disparity error, a lateral one an image-position error), so Euclidean
// nearest neighbours there are nearest in the noise metric with each point's
// own ray. The grid holds the surface points facing the camera, mapped with
// the camera placed where the estimate at build time puts it; later
// estimates move the sensed points against that frozen camera, which changes
// their rays by the small difference between the two poses.
struct MetricSearch {
  Eigen::Isometry3d camera_from_tanker = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d camera_from_receiver = Eigen::Isometry3d::Identity();  // at build time
  double lateral_scale = 1.0;                                              // f / sigma_px
  double disparity_scale = 1.0;                                            // f b / sigma_d
  std::vector<uint32_t> index;                                             // search point -> surface point
  std::unique_ptr<SheetGrid3d> tree;

  // The search-space point of `in_camera` (camera frame); false behind the camera.
  bool MapFromCamera(const Eigen::Vector3d& in_camera, Eigen::Vector3d& out) const {
    const double z = in_camera.z();
    if (!(z > 0.0)) return false;
    out = Eigen::Vector3d(lateral_scale * in_camera.x() / z, lateral_scale * in_camera.y() / z, disparity_scale / z);
    return true;
  }
  // The search-space point of `in_receiver`; false behind the camera.
  bool Map(const Eigen::Vector3d& in_receiver, Eigen::Vector3d& out) const {
    return MapFromCamera(camera_from_receiver * in_receiver, out);
  }
};

MetricSearch BuildMetricSearch(const std::vector<Eigen::Vector3d>& surface,
                               const std::vector<Eigen::Vector3d>& surface_normals, const StereoNoiseGeometry& g,
                               const PlaneIcpOptions& o, const Eigen::Isometry3d& tanker_from_receiver) {
  MetricSearch search;
  // Camera axes: z the optical axis; x and y any orthonormal pair (the metric is symmetric about z).
  const Eigen::Vector3d z = g.optical_axis_in_tanker.normalized();
  const Eigen::Vector3d x = z.unitOrthogonal();
  Eigen::Matrix3d tanker_from_camera;
  tanker_from_camera << x, z.cross(x), z;
  search.camera_from_tanker.linear() = tanker_from_camera.transpose();
  search.camera_from_tanker.translation() = -tanker_from_camera.transpose() * g.camera_centre_in_tanker;
  search.camera_from_receiver = search.camera_from_tanker * tanker_from_receiver;
  search.lateral_scale = g.focal_px / std::max(o.lateral_noise_px, 1e-9);
  search.disparity_scale = g.focal_times_baseline_px_m / std::max(o.disparity_noise_px, 1e-9);
  // A point faces the camera when its normal points towards the camera's
  // centre: tested in the receiver's frame, so that only the facing half of
  // the surface is transformed.
  const Eigen::Vector3d camera_in_receiver = search.camera_from_receiver.inverse().translation();
  std::vector<Eigen::Vector3d> points;
  points.reserve(surface.size());
  search.index.reserve(surface.size());
  for (size_t j = 0; j < surface.size(); ++j) {
    if (!(surface_normals[j].dot(surface[j] - camera_in_receiver) < 0.0)) continue;
    Eigen::Vector3d mapped;
    if (search.MapFromCamera(search.camera_from_receiver * surface[j], mapped)) {
      search.index.push_back(static_cast<uint32_t>(j));
      points.push_back(mapped);
    }
  }
  if (points.empty()) throw Error("point-to-plane ICP: no model surface faces the cameras");
  search.tree = std::make_unique<SheetGrid3d>(std::move(points));
  return search;
}

// What one Register call pairs: the sensed cloud with its noise and centre,
// the surface its points pair with (the pairing surface, or the model), and
// the model whose points pair back in kSymmetric.
struct PairingInputs {
  const std::vector<Eigen::Vector3d>& sensed;
  const std::vector<SensedNoise>& noise;
  const Eigen::Vector3d& centre;
  const std::vector<Eigen::Vector3d>& surface;
  const std::vector<Eigen::Vector3d>& surface_normals;
  const std::vector<Eigen::Vector3d>& model;
  const std::vector<Eigen::Vector3d>& model_normals;
  const StereoNoiseGeometry& geometry;
  const PlaneIcpOptions& options;
};

// One Register call's nearest-neighbour searches: sensed to surface (in
// metres, or kMahalanobis's metric search) and, kSymmetric, model to sensed.
struct PairingSearches {
  std::unique_ptr<CachedNearest> to_model;
  // kMahalanobis: its distances are not metres, so no radius. Rebuilt when
  // the camera's rays through the receiver have turned by more than
  // sigma_lat / sigma_ray (median over the cloud) since: beyond that, an
  // along-ray error of one sigma would be mistaken for a lateral one of one sigma.
  MetricSearch metric;
  std::unique_ptr<CachedNearest> to_metric;
  double max_ray_turn_rad = 0.0, range_m = 0.0;
  std::unique_ptr<KdTree3d> sensed_tree;
  std::unique_ptr<CachedNearest> to_sensed;

  void BuildMetric(const PairingInputs& in, const Eigen::Isometry3d& tanker_from_receiver) {
    metric = BuildMetricSearch(in.surface, in.surface_normals, in.geometry, in.options, tanker_from_receiver);
    to_metric =
        std::make_unique<CachedNearest>(*metric.tree, in.sensed.size(), true, std::numeric_limits<double>::infinity());
  }

  // kMahalanobis: rebuilds the metric search when the estimate has turned
  // the rays by more than max_ray_turn_rad since it was built.
  void UpdateMetric(const PairingInputs& in, const Eigen::Isometry3d& tanker_from_receiver) {
    const Eigen::Isometry3d receiver_from_camera_then = metric.camera_from_receiver.inverse();
    const Eigen::Isometry3d camera_now_from_receiver = metric.camera_from_tanker * tanker_from_receiver;
    const Eigen::Isometry3d change = camera_now_from_receiver * receiver_from_camera_then;
    const double turn =
        Eigen::AngleAxisd(change.linear()).angle() +
        (receiver_from_camera_then.translation() - camera_now_from_receiver.inverse().translation()).norm() / range_m;
    if (turn > max_ray_turn_rad) BuildMetric(in, tanker_from_receiver);
  }
};

// The searches of one Register call, the metric search built at the initial
// estimate; `surface_tree` holds in.surface.
PairingSearches MakeSearches(const PairingInputs& in, const NearestSearch3d& surface_tree,
                             const Eigen::Isometry3d& initial_tanker_from_receiver) {
  const PlaneIcpOptions& o = in.options;
  const bool metric = o.pairing == PlanePairing::kMahalanobis;
  double max_gate_squared = 0.0;
  for (const SensedNoise& n : in.noise) max_gate_squared = std::max(max_gate_squared, n.gate_squared);
  const double search_radius = std::sqrt(max_gate_squared);
  PairingSearches searches;
  if (metric) {
    std::vector<double> ratios, ranges;
    for (size_t i = 0; i < in.sensed.size(); ++i) {
      ratios.push_back(std::sqrt(in.noise[i].lateral_variance / in.noise[i].ray_variance));
      ranges.push_back((in.sensed[i] - in.geometry.camera_centre_in_tanker).norm());
    }
    searches.max_ray_turn_rad = UpperMedian(ratios);
    searches.range_m = UpperMedian(ranges);
    searches.BuildMetric(in, initial_tanker_from_receiver);
  }
  searches.to_model = std::make_unique<CachedNearest>(surface_tree, metric ? 0 : in.sensed.size(), true, search_radius);
  if (o.pairing == PlanePairing::kSymmetric) {
    searches.sensed_tree = std::make_unique<KdTree3d>(in.sensed, o.kdtree_leaf_size);
    searches.to_sensed = std::make_unique<CachedNearest>(*searches.sensed_tree, in.model.size(), true, search_radius);
  }
  return searches;
}

// Adds every coarse-th sensed point's pair with the surface to `equations`
// (weighted coarse); returns the pairs found within their gates.
size_t AddSensedPairs(const PairingInputs& in, PairingSearches& searches, const Eigen::Isometry3d& tanker_from_receiver,
                      size_t coarse, NormalEquations& equations, double& sum_squared) {
  const PlaneIcpOptions& o = in.options;
  const bool metric = o.pairing == PlanePairing::kMahalanobis;
  const Eigen::Isometry3d receiver_from_tanker = tanker_from_receiver.inverse();
  const Eigen::Matrix3d rotation = tanker_from_receiver.linear();
  size_t inliers = 0;
  for (size_t i = 0; i < in.sensed.size(); i += coarse) {
    const Eigen::Vector3d in_receiver = receiver_from_tanker * in.sensed[i];
    size_t j = CachedNearest::kNone;
    double squared = 0.0;
    if (metric) {
      Eigen::Vector3d mapped;
      if (!searches.metric.Map(in_receiver, mapped)) continue;
      j = searches.to_metric->Find(i, mapped).first;
      if (j == CachedNearest::kNone) continue;
      j = searches.metric.index[j];
      squared = SquaredDistance(in_receiver, in.surface[j]);
    } else {
      std::tie(j, squared) = searches.to_model->Find(i, in_receiver);
      if (j == CachedNearest::kNone) continue;
    }
    const SensedNoise& noise = in.noise[i];
    if (squared > noise.gate_squared) continue;
    const Eigen::Vector3d p = tanker_from_receiver * in.surface[j];
    const Eigen::Vector3d n = rotation * in.surface_normals[j];
    const Eigen::Vector3d& sensed = in.sensed[i];
    const double weight = static_cast<double>(coarse);
    if (o.residual == PlaneResidual::kMetric) {
      equations.Add(p, n, sensed, noise, in.centre, o, weight, sum_squared, sensed);
    } else if (o.residual == PlaneResidual::kMetricRay) {
      equations.Add(p, n, sensed, noise, in.centre, o, weight, sum_squared, RayLever(p, n, sensed, noise, in.geometry));
    } else if (!equations.AddDisparity(p, n, sensed, noise, in.geometry, in.centre, o, weight, sum_squared)) {
      // Oblique to the ray: the metric residual, its noise and lever arm from the model point.
      equations.Add(p, n, sensed, NoiseAt(p, in.geometry, o), in.centre, o, weight, sum_squared, p);
    }
    ++inliers;
  }
  return inliers;
}

// kSymmetric: adds the model points' pairs with the sensed cloud.
void AddModelPairs(const PairingInputs& in, PairingSearches& searches, const Eigen::Isometry3d& tanker_from_receiver,
                   size_t coarse, NormalEquations& equations) {
  const PlaneIcpOptions& o = in.options;
  const Eigen::Matrix3d rotation = tanker_from_receiver.linear();
  double unused = 0.0;
  // Each direction weighs as much in total as the other, whatever the
  // model's and the cloud's sizes.
  const double balance =
      o.balance_directions ? static_cast<double>(in.sensed.size()) / static_cast<double>(in.model.size()) : 1.0;
  // Every stride-th model point, each standing for stride of them.
  const size_t stride =
      coarse * (o.max_model_queries > 0 ? (in.model.size() + o.max_model_queries - 1) / o.max_model_queries : 1);
  for (size_t j = 0; j < in.model.size(); j += stride) {
    const Eigen::Vector3d p = tanker_from_receiver * in.model[j];
    const auto [i, squared] = searches.to_sensed->Find(j, p);
    if (i == CachedNearest::kNone || squared > in.noise[i].gate_squared) continue;
    const SensedNoise& noise = in.noise[i];
    const double pull = o.model_pull_scale_m > 0.0
                            ? noise.ray_variance / (noise.ray_variance + o.model_pull_scale_m * o.model_pull_scale_m)
                            : 1.0;
    equations.Add(p, rotation * in.model_normals[j], in.sensed[i], noise, in.centre, o,
                  pull * balance * static_cast<double>(stride), unused, in.sensed[i]);
  }
}

// p -> centre + R_w (p - centre) + v for step = (w, v), applied after
// tanker_from_receiver.
Eigen::Isometry3d ApplyStep(const Eigen::Matrix<double, 6, 1>& step, const Eigen::Vector3d& centre,
                            const Eigen::Isometry3d& tanker_from_receiver) {
  const Eigen::Vector3d w = step.head<3>();
  const double angle = w.norm();
  Eigen::Isometry3d increment = Eigen::Isometry3d::Identity();
  if (angle > 0.0) increment.linear() = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
  increment.translation() = centre + step.tail<3>() - increment.linear() * centre;
  return increment * tanker_from_receiver;
}

}  // namespace

std::string ToString(PlanePairing pairing) {
  switch (pairing) {
    case PlanePairing::kSensedToModel:
      return "sensed_to_model";
    case PlanePairing::kSymmetric:
      return "symmetric";
    case PlanePairing::kMahalanobis:
      return "mahalanobis";
  }
  return "unknown";
}

std::string ToString(PlaneResidual residual) {
  switch (residual) {
    case PlaneResidual::kDisparity:
      return "disparity";
    case PlaneResidual::kMetricRay:
      return "metric-ray";
    case PlaneResidual::kMetric:
      break;
  }
  return "metric";
}

PlaneResidual ParsePlaneResidual(const std::string& text) {
  if (text == "metric") return PlaneResidual::kMetric;
  if (text == "disparity") return PlaneResidual::kDisparity;
  if (text == "metric-ray") return PlaneResidual::kMetricRay;
  throw Error("point-to-plane residual '" + text + "': expected metric, disparity or metric-ray");
}

PlanePairing ParsePlanePairing(const std::string& text) {
  if (text == "sensed_to_model") return PlanePairing::kSensedToModel;
  if (text == "symmetric") return PlanePairing::kSymmetric;
  if (text == "mahalanobis") return PlanePairing::kMahalanobis;
  throw Error("point-to-plane pairing '" + text + "': expected sensed_to_model, symmetric or mahalanobis");
}

void PlaneIcpOptions::Check() const {
  if (max_iterations < 0) throw Error("point-to-plane ICP: max_iterations must be >= 0");
  if (!(translation_tolerance_m >= 0.0)) throw Error("point-to-plane ICP: translation_tolerance_m must be >= 0");
  if (!(rotation_tolerance_rad >= 0.0)) throw Error("point-to-plane ICP: rotation_tolerance_rad must be >= 0");
  if (!(max_correspondence_distance_m > 0.0)) {
    throw Error("point-to-plane ICP: max_correspondence_distance_m must be > 0");
  }
  if (!(robust_scale > 0.0)) throw Error("point-to-plane ICP: robust_scale must be > 0");
  if (max_model_queries > 100000000) throw Error("point-to-plane ICP: max_model_queries is too large");
  if (!(model_pull_scale_m >= 0.0) || !std::isfinite(model_pull_scale_m)) {
    throw Error("point-to-plane ICP: model_pull_scale_m must be finite and >= 0");
  }
  if (!(gate_sigmas >= 0.0)) throw Error("point-to-plane ICP: gate_sigmas must be >= 0");
  // The pairing's metric and the weights divide by the disparity noise: zero would make every pair infinitely sure.
  if (!(disparity_noise_px > 0.0 && disparity_noise_px <= 100.0)) {
    throw Error("--disparity-noise " + FormatFixed(disparity_noise_px, 3) +
                ": the ICP's stereo noise model needs a disparity noise in (0, 100] px");
  }
  if (!(lateral_noise_px >= 0.0) || !(surface_noise_m > 0.0) || !std::isfinite(lateral_noise_px) ||
      !std::isfinite(surface_noise_m)) {
    throw Error("point-to-plane ICP: noise model needs lateral noise >= 0 and surface noise > 0");
  }
  if (kdtree_leaf_size < 1) throw Error("point-to-plane ICP: kdtree_leaf_size must be >= 1");
  if (!(converged_chi2 >= 0.0)) throw Error("point-to-plane ICP: converged_chi2 must be >= 0");
  if (noise_bias_correction && (residual != PlaneResidual::kMetric || pairing == PlanePairing::kSymmetric)) {
    throw Error(
        "--noise-bias-correction: only with the metric residual and sensed-to-model pairs (not --pairing "
        "symmetric, --residual " +
        ToString(residual) + ")");
  }
}

PlaneIcpRegistration::PlaneIcpRegistration(std::vector<Eigen::Vector3d> model_points_in_receiver,
                                           std::vector<Eigen::Vector3d> model_normals_in_receiver,
                                           const StereoNoiseGeometry& geometry, const PlaneIcpOptions& options)
    : model_(std::move(model_points_in_receiver)),
      normals_(std::move(model_normals_in_receiver)),
      geometry_(geometry),
      options_(options) {
  options_.Check();
  if (model_.empty()) throw Error("point-to-plane ICP: the reference model is empty");
  if (normals_.size() != model_.size()) throw Error("point-to-plane ICP: the model needs one normal per point");
  CheckFinitePoints(model_, "point-to-plane ICP: model point");
  CheckFinitePoints(normals_, "point-to-plane ICP: model normal");
  if (!(geometry_.focal_px > 0.0) || !(geometry_.focal_times_baseline_px_m > 0.0)) {
    throw Error("point-to-plane ICP: the noise geometry needs positive f and f b");
  }
  model_tree_ = std::make_unique<KdTree3d>(model_, options_.kdtree_leaf_size);
}

PlaneIcpRegistration::~PlaneIcpRegistration() = default;

void PlaneIcpRegistration::SetSensedPairingSurface(std::vector<Eigen::Vector3d> points_in_receiver,
                                                   std::vector<Eigen::Vector3d> normals_in_receiver) {
  if (points_in_receiver.empty() || normals_in_receiver.size() != points_in_receiver.size()) {
    throw Error("point-to-plane ICP: the pairing surface needs points and one normal per point");
  }
  CheckFinitePoints(points_in_receiver, "point-to-plane ICP: surface point");
  CheckFinitePoints(normals_in_receiver, "point-to-plane ICP: surface normal");
  surface_ = std::move(points_in_receiver);
  surface_normals_ = std::move(normals_in_receiver);
  surface_tree_ = std::make_unique<KdTree3d>(surface_, options_.kdtree_leaf_size);
}

RegistrationResult PlaneIcpRegistration::Register(const std::vector<Eigen::Vector3d>& sensed,
                                                  const Eigen::Isometry3d& initial_tanker_from_receiver) const {
  if (sensed.empty()) throw Error("point-to-plane ICP: the sensed point cloud is empty");
  CheckFinitePoints(sensed, "point-to-plane ICP: sensed point");
  const PlaneIcpOptions& o = options_;
  const bool metric = o.pairing == PlanePairing::kMahalanobis;
  const std::vector<SensedNoise> noise = NoiseOf(sensed, geometry_, o);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& s : sensed) centre += s;
  centre /= static_cast<double>(sensed.size());
  const bool own_surface = !surface_.empty();
  const PairingInputs in{
      sensed,   noise,     centre, own_surface ? surface_ : model_, own_surface ? surface_normals_ : normals_, model_,
      normals_, geometry_, o};
  PairingSearches searches =
      MakeSearches(in, own_surface ? *surface_tree_ : *model_tree_, initial_tanker_from_receiver);

  RegistrationResult result;
  result.tanker_from_receiver = initial_tanker_from_receiver;
  // Coarse phase: every coarse_stride-th point of both clouds (weighted
  // coarse_stride) until the steps fall below ten times the tolerances; the
  // fine phase then uses every point. Early steps are large and miss the
  // nearest-neighbour cache, so they are the expensive ones.
  size_t coarse =
      std::max<size_t>(1, std::min(o.coarse_stride, sensed.size() / std::max<size_t>(1, o.coarse_min_points)));
  for (int k = 0;; ++k) {
    if (metric) searches.UpdateMetric(in, result.tanker_from_receiver);
    NormalEquations equations;
    equations.noise_bias = o.noise_bias_correction && coarse == 1;
    double sum_squared = 0.0;
    const size_t inliers =
        coarse * AddSensedPairs(in, searches, result.tanker_from_receiver, coarse, equations, sum_squared);
    if (o.pairing == PlanePairing::kSymmetric)
      AddModelPairs(in, searches, result.tanker_from_receiver, coarse, equations);
    const double rmse =
        inliers > 0 ? std::sqrt(sum_squared * static_cast<double>(coarse) / static_cast<double>(inliers)) : 0.0;
    if (k == 0) result.initial_rmse_m = rmse;
    result.num_inliers = inliers;
    result.rmse_m = rmse;
    result.fitness = static_cast<double>(inliers) / static_cast<double>(sensed.size());
    if (result.converged || k == o.max_iterations || inliers < 6) {
      if (equations.noise_bias && inliers >= 6) {
        double scale_squared = 0.0;
        const Eigen::Matrix<double, 6, 1> step = equations.NoiseBiasStep(scale_squared);
        if (step.allFinite()) {
          result.tanker_from_receiver = ApplyStep(step, centre, result.tanker_from_receiver);
          result.noise_scale = std::sqrt(scale_squared);
        }
      }
      break;
    }

    const Eigen::Matrix<double, 6, 1> step = equations.Solve();
    if (!step.allFinite()) break;
    const double angle = step.head<3>().norm();
    const double move = step.tail<3>().norm();
    result.tanker_from_receiver = ApplyStep(step, centre, result.tanker_from_receiver);
    ++result.iterations;
    if (coarse > 1) {
      if (move < 10.0 * o.translation_tolerance_m && angle < 10.0 * o.rotation_tolerance_rad) coarse = 1;
      continue;
    }
    // One more association after convergence gives the final statistics.
    // kMahalanobis: also converged when the step is small against the
    // estimate's own uncertainty, step^T H step = -g . step (chi^2 units, H
    // weighted by 1 / sigma^2), as its pairs keep switching by less than that.
    const bool within_noise = metric && -equations.g.dot(step) < o.converged_chi2;
    result.converged = (move < o.translation_tolerance_m && angle < o.rotation_tolerance_rad) || within_noise;
  }
  return result;
}

}  // namespace aar
