#include "aar/analyzer/icp.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "aar/analyzer/nearest_cache.h"
#include "aar/error.h"

namespace aar {

namespace {

// Pairs (model point in receiver frame, sensed point in tanker frame) of one
// iteration and the sum of their squared distances.
struct Pairs {
  std::vector<Eigen::Vector3d> model;
  std::vector<Eigen::Vector3d> sensed;
  double sum_squared = 0.0;
  size_t queries = 0;

  double Mse() const { return model.empty() ? 0.0 : sum_squared / static_cast<double>(model.size()); }
};

}  // namespace

std::string ToString(IcpCorrespondence correspondence) {
  return correspondence == IcpCorrespondence::kModelToSensed ? "model_to_sensed" : "sensed_to_model";
}

IcpCorrespondence ParseIcpCorrespondence(const std::string& text) {
  if (text == "model_to_sensed") return IcpCorrespondence::kModelToSensed;
  if (text == "sensed_to_model") return IcpCorrespondence::kSensedToModel;
  throw Error("ICP correspondence '" + text + "' is not model_to_sensed or sensed_to_model");
}

void IcpOptions::Check() const {
  if (max_iterations < 0) throw Error("ICP: max_iterations must be >= 0");
  if (!(relative_mse_tolerance >= 0.0)) throw Error("ICP: relative_mse_tolerance must be >= 0");
  if (!(translation_tolerance_m >= 0.0)) throw Error("ICP: translation_tolerance_m must be >= 0");
  if (!(rotation_tolerance_rad >= 0.0)) throw Error("ICP: rotation_tolerance_rad must be >= 0");
  if (!(max_correspondence_distance_m > 0.0)) throw Error("ICP: max_correspondence_distance_m must be > 0");
  if (kdtree_leaf_size < 1) throw Error("ICP: kdtree_leaf_size must be >= 1");
}

Eigen::Isometry3d RigidTransformFromPairs(const std::vector<Eigen::Vector3d>& a,
                                          const std::vector<Eigen::Vector3d>& b) {
  if (a.size() != b.size() || a.empty()) throw Error("RigidTransformFromPairs: need equally many (>= 1) points");
  const double n = static_cast<double>(a.size());
  Eigen::Vector3d mean_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < a.size(); ++i) {
    mean_a += a[i];
    mean_b += b[i];
  }
  mean_a /= n;
  mean_b /= n;
  // Cross-covariance H = sum (a_i - mean_a)(b_i - mean_b)^T; with H = U S V^T
  // the optimal rotation is V diag(1, 1, det(V U^T)) U^T (Umeyama 1991, eq. 39-40).
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < a.size(); ++i) h.noalias() += (a[i] - mean_a) * (b[i] - mean_b).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  Eigen::Isometry3d b_from_a = Eigen::Isometry3d::Identity();
  b_from_a.linear() = svd.matrixV() * d * svd.matrixU().transpose();
  b_from_a.translation() = mean_b - b_from_a.linear() * mean_a;
  return b_from_a;
}

Eigen::Isometry3d InitialGuessAtCentroid(const std::vector<Eigen::Vector3d>& sensed_points_in_tanker,
                                         const std::vector<Eigen::Vector3d>& model_points_in_receiver) {
  if (sensed_points_in_tanker.empty() || model_points_in_receiver.empty()) {
    throw Error("ICP seed: the sensed cloud and the model must not be empty");
  }
  const auto centroid = [](const std::vector<Eigen::Vector3d>& points) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : points) sum += p;
    return Eigen::Vector3d(sum / static_cast<double>(points.size()));
  };
  Eigen::Isometry3d tanker_from_receiver = Eigen::Isometry3d::Identity();
  tanker_from_receiver.translation() = centroid(sensed_points_in_tanker) - centroid(model_points_in_receiver);
  return tanker_from_receiver;
}

IcpRegistration::IcpRegistration(std::vector<Eigen::Vector3d> model_points_in_receiver, const IcpOptions& options)
    : model_(std::move(model_points_in_receiver)), options_(options) {
  options_.Check();
  if (model_.empty()) throw Error("ICP: the reference model is empty");
  CheckFinitePoints(model_, "ICP: model point");
  if (options_.correspondence == IcpCorrespondence::kSensedToModel) {
    model_tree_ = std::make_unique<KdTree3d>(model_, options_.kdtree_leaf_size);
  }
}

IcpRegistration::~IcpRegistration() = default;

RegistrationResult IcpRegistration::Register(const std::vector<Eigen::Vector3d>& sensed,
                                             const Eigen::Isometry3d& initial_tanker_from_receiver) const {
  if (sensed.empty()) throw Error("ICP: the sensed point cloud is empty");
  CheckFinitePoints(sensed, "ICP: sensed point");
  const bool model_to_sensed = options_.correspondence == IcpCorrespondence::kModelToSensed;
  std::unique_ptr<KdTree3d> sensed_tree;
  if (model_to_sensed) sensed_tree = std::make_unique<KdTree3d>(sensed, options_.kdtree_leaf_size);
  CachedNearest nearest(model_to_sensed ? *sensed_tree : *model_tree_, model_to_sensed ? model_.size() : sensed.size(),
                        options_.cache_nearest, options_.max_correspondence_distance_m);
  const double max_squared = options_.max_correspondence_distance_m * options_.max_correspondence_distance_m;

  // Data association at tanker_from_receiver, in query order.
  Pairs pairs;
  pairs.model.reserve(model_to_sensed ? model_.size() : sensed.size());
  pairs.sensed.reserve(pairs.model.capacity());
  const auto associate = [&](const Eigen::Isometry3d& tanker_from_receiver) {
    pairs.model.clear();
    pairs.sensed.clear();
    pairs.sum_squared = 0.0;
    if (model_to_sensed) {
      pairs.queries = model_.size();
      for (size_t i = 0; i < model_.size(); ++i) {
        const auto [j, squared] = nearest.Find(i, tanker_from_receiver * model_[i]);
        if (j == CachedNearest::kNone || squared > max_squared) continue;
        pairs.model.push_back(model_[i]);
        pairs.sensed.push_back(sensed[j]);
        pairs.sum_squared += squared;
      }
    } else {
      pairs.queries = sensed.size();
      const Eigen::Isometry3d receiver_from_tanker = tanker_from_receiver.inverse();
      for (size_t i = 0; i < sensed.size(); ++i) {
        const auto [j, squared] = nearest.Find(i, receiver_from_tanker * sensed[i]);
        if (j == CachedNearest::kNone || squared > max_squared) continue;
        pairs.model.push_back(model_[j]);
        pairs.sensed.push_back(sensed[i]);
        pairs.sum_squared += squared;
      }
    }
  };

  RegistrationResult result;
  result.tanker_from_receiver = initial_tanker_from_receiver;
  double previous_mse = 0.0;
  bool stop_after_association = false;
  for (int k = 0;; ++k) {
    associate(result.tanker_from_receiver);
    const double mse = pairs.Mse();
    if (k == 0) result.initial_rmse_m = std::sqrt(mse);
    if (stop_after_association) break;
    if (k > 0 && (mse == 0.0 || std::abs(previous_mse - mse) < options_.relative_mse_tolerance * previous_mse)) {
      result.converged = true;
      break;
    }
    if (k == options_.max_iterations || pairs.model.size() < 3) break;
    previous_mse = mse;
    // Closed-form step (Besl-McKay): the transform that best maps the paired
    // model points onto their sensed partners, solved from scratch each time.
    const Eigen::Isometry3d updated = RigidTransformFromPairs(pairs.model, pairs.sensed);
    const Eigen::Isometry3d increment = updated * result.tanker_from_receiver.inverse();
    result.tanker_from_receiver = updated;
    ++result.iterations;
    const double angle = Eigen::AngleAxisd(increment.linear()).angle();
    if (increment.translation().norm() < options_.translation_tolerance_m && angle < options_.rotation_tolerance_rad) {
      result.converged = true;
      stop_after_association = true;  // one more association for the final statistics
    }
  }
  result.num_inliers = pairs.model.size();
  result.rmse_m = std::sqrt(pairs.Mse());
  result.fitness = static_cast<double>(pairs.model.size()) / static_cast<double>(pairs.queries);
  return result;
}

RegistrationResult RegisterIcp(const std::vector<Eigen::Vector3d>& model_points_in_receiver,
                               const std::vector<Eigen::Vector3d>& sensed_points_in_tanker,
                               const Eigen::Isometry3d& initial_tanker_from_receiver, const IcpOptions& options) {
  return IcpRegistration(model_points_in_receiver, options)
      .Register(sensed_points_in_tanker, initial_tanker_from_receiver);
}

}  // namespace aar
