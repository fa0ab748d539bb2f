#include "aar/analyzer/bop_metrics.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>

#include "aar/error.h"

namespace aar {
namespace {

std::vector<Eigen::Vector3d> DistinctVertices(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> unique = mesh.vertices;
  std::sort(unique.begin(), unique.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
  return unique;
}

// Fraction of `errors` (misses: nullopt) strictly below `threshold`.
template <class Get>
double Recall(const std::vector<std::optional<PoseErrorMetrics>>& errors, double threshold, Get get) {
  size_t hits = 0;
  for (const std::optional<PoseErrorMetrics>& e : errors) hits += e && get(*e) < threshold ? 1 : 0;
  return static_cast<double>(hits) / static_cast<double>(errors.size());
}

// The largest distance between two of `points`, exactly, without testing
// every pair: with the points sorted by their distance r from the centroid,
// |p - q| <= r_p + r_q (the triangle inequality), so once that bound is
// below the best distance found no later pair can beat it. Of an aircraft's
// vertices only those near the extremities are paired.
double PointSetDiameter(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 2) return 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  std::vector<std::pair<double, size_t>> by_radius;
  by_radius.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) by_radius.emplace_back((points[i] - centroid).norm(), i);
  std::sort(by_radius.begin(), by_radius.end(), std::greater<>());
  // A margin far above the rounding of the bounds keeps the pruning exact.
  const double margin = 1e-9 * (1.0 + by_radius.front().first);
  double best_sq = 0.0, best = 0.0;
  for (size_t a = 0; a < by_radius.size(); ++a) {
    if (by_radius[a].first + by_radius.front().first < best - margin) break;
    const Eigen::Vector3d& p = points[by_radius[a].second];
    for (size_t b = a + 1; b < by_radius.size(); ++b) {
      if (by_radius[a].first + by_radius[b].first < best - margin) break;
      const double d_sq = (p - points[by_radius[b].second]).squaredNorm();
      if (d_sq > best_sq) {
        best_sq = d_sq;
        best = std::sqrt(best_sq);
      }
    }
  }
  return best;
}

}  // namespace

BopObject::BopObject(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> vertices = DistinctVertices(mesh);
  if (vertices.size() < 2) throw Error("BOP metrics: the model has fewer than two distinct vertices");
  diameter_m_ = PointSetDiameter(vertices);
  tree_ = std::make_unique<KdTree3d>(std::move(vertices));
}

PoseErrorMetrics ComputePoseErrorMetrics(const BopObject& object, const Intrinsics& camera,
                                         const Eigen::Isometry3d& cam_from_model_estimate,
                                         const Eigen::Isometry3d& cam_from_model_truth) {
  const auto project = [&camera](const Eigen::Vector3d& p) -> std::optional<Eigen::Vector2d> {
    if (!(p.z() > 0.0)) return std::nullopt;
    return Eigen::Vector2d(camera.fx_px * p.x() / p.z() + camera.cx_px, camera.fy_px * p.y() / p.z() + camera.cy_px);
  };
  // ADD-S's nearest true vertex, searched in the model frame: |P' x1 - P x2|
  // = |P^-1 P' x1 - x2| for rigid P.
  const Eigen::Isometry3d truth_model_from_estimate_model = cam_from_model_truth.inverse() * cam_from_model_estimate;
  PoseErrorMetrics m;
  double add_sum = 0.0, adds_sum = 0.0;
  for (const Eigen::Vector3d& x : object.vertices()) {
    const Eigen::Vector3d estimated = cam_from_model_estimate * x, truth = cam_from_model_truth * x;
    const double distance = (estimated - truth).norm();
    m.mssd_m = std::max(m.mssd_m, distance);
    add_sum += distance;
    adds_sum += std::sqrt(object.tree().Nearest(truth_model_from_estimate_model * x).second);
    const std::optional<Eigen::Vector2d> a = project(estimated), b = project(truth);
    m.mspd_px = std::max(m.mspd_px, a && b ? (*a - *b).norm() : std::numeric_limits<double>::infinity());
  }
  const double n = static_cast<double>(object.vertices().size());
  m.add_m = add_sum / n;
  m.adds_m = adds_sum / n;
  return m;
}

BopScores ScoreBop(const std::vector<std::optional<PoseErrorMetrics>>& errors, const BopScale& scale) {
  if (!(scale.diameter_m > 0.0) || scale.image_width_px <= 0) {
    throw Error("BOP scores: the object's diameter and the image width must be positive");
  }
  BopScores s;
  s.targets = errors.size();
  if (errors.empty()) return s;
  for (double fraction : kMssdThresholdFractions) {
    s.ar_mssd += Recall(errors, fraction * scale.diameter_m, [](const PoseErrorMetrics& e) { return e.mssd_m; });
  }
  s.ar_mssd /= static_cast<double>(kMssdThresholdFractions.size());
  const double r = scale.image_width_px / 640.0;
  for (double threshold : kMspdThresholdsPx640) {
    s.ar_mspd += Recall(errors, threshold * r, [](const PoseErrorMetrics& e) { return e.mspd_px; });
  }
  s.ar_mspd /= static_cast<double>(kMspdThresholdsPx640.size());
  s.ar_mssd_mspd = 0.5 * (s.ar_mssd + s.ar_mspd);
  const double add_threshold = kAddThresholdFraction * scale.diameter_m;
  s.add_recall = Recall(errors, add_threshold, [](const PoseErrorMetrics& e) { return e.add_m; });
  s.adds_recall = Recall(errors, add_threshold, [](const PoseErrorMetrics& e) { return e.adds_m; });
  if (std::any_of(errors.begin(), errors.end(), [](const auto& e) { return e && e->vsd; })) {
    double sum = 0.0;
    for (size_t t = 0; t < kVsdTauFractions.size(); ++t) {
      for (double theta : kVsdThresholds) {
        sum += Recall(errors, theta, [t](const PoseErrorMetrics& e) { return e.vsd ? (*e.vsd)[t] : 1.0; });
      }
    }
    s.ar_vsd = sum / static_cast<double>(kVsdTauFractions.size() * kVsdThresholds.size());
    s.ar = (*s.ar_vsd + s.ar_mssd + s.ar_mspd) / 3.0;
  }
  return s;
}

}  // namespace aar
