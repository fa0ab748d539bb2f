#include "aar/analyzer/icp.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <string>

#include <Eigen/SVD>
#include <nanoflann.hpp>

#include "aar/error.h"

namespace aar {

// ---- KD-tree ----

namespace {

struct PointsAdaptor {
  const std::vector<Eigen::Vector3d>* points = nullptr;
  size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(size_t index, size_t dim) const { return (*points)[index][static_cast<Eigen::Index>(dim)]; }
  template <class BoundingBox>
  bool kdtree_get_bbox(BoundingBox&) const {
    return false;  // let nanoflann compute it
  }
};

// |a - b|^2 summed in nanoflann's order (L2_Simple_Adaptor::evalMetric), so
// distances computed here and inside the tree are bitwise equal.
double SquaredDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  double result = 0.0;
  for (Eigen::Index i = 0; i < 3; ++i) {
    const double diff = a[i] - b[i];
    result += diff * diff;
  }
  return result;
}

// k-nearest result set (nanoflann's RESULTSET interface) that can be seeded
// with candidate points before the search, so that their distances bound the
// search from the first node, and that ignores points at or beyond a radius.
// Points already held are not added twice (a seed met again in the tree).
class BoundedKnn {
 public:
  BoundedKnn(size_t capacity, uint32_t* indices, double* squared, double max_squared)
      : capacity_(capacity), indices_(indices), squared_(squared), max_squared_(max_squared) {}
  size_t size() const { return count_; }
  bool full() const { return count_ == capacity_; }
  double worstDist() const { return count_ < capacity_ ? max_squared_ : squared_[capacity_ - 1]; }
  bool addPoint(double squared, uint32_t index) {
    if (!(squared < worstDist())) return true;
    for (size_t i = 0; i < count_; ++i) {
      if (indices_[i] == index) return true;
    }
    size_t i = count_ < capacity_ ? count_++ : capacity_ - 1;
    for (; i > 0 && squared_[i - 1] > squared; --i) {  // insertion keeps earlier equal distances first
      squared_[i] = squared_[i - 1];
      indices_[i] = indices_[i - 1];
    }
    squared_[i] = squared;
    indices_[i] = index;
    return true;  // keep searching
  }

 private:
  size_t capacity_;
  uint32_t* indices_;
  double* squared_;
  double max_squared_;
  size_t count_ = 0;
};

using NanoflannTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>,
                                                          PointsAdaptor, 3, uint32_t>;

}  // namespace

struct KdTree3d::Impl {
  std::vector<Eigen::Vector3d> points;
  PointsAdaptor adaptor;
  std::unique_ptr<NanoflannTree> tree;
};

KdTree3d::KdTree3d(std::vector<Eigen::Vector3d> points, int leaf_size) : impl_(std::make_unique<Impl>()) {
  if (points.size() > static_cast<size_t>(UINT32_MAX)) throw Error("KdTree3d: too many points");
  impl_->points = std::move(points);
  impl_->adaptor.points = &impl_->points;  // stable: Impl lives on the heap
  impl_->tree = std::make_unique<NanoflannTree>(
      3, impl_->adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(static_cast<size_t>(std::max(1, leaf_size))));
}

KdTree3d::~KdTree3d() = default;
KdTree3d::KdTree3d(KdTree3d&&) noexcept = default;
KdTree3d& KdTree3d::operator=(KdTree3d&&) noexcept = default;

const std::vector<Eigen::Vector3d>& KdTree3d::points() const { return impl_->points; }

std::pair<size_t, double> KdTree3d::Nearest(const Eigen::Vector3d& query) const {
  if (impl_->points.empty()) throw Error("KdTree3d: nearest-neighbour query on an empty tree");
  uint32_t index = 0;
  double squared = 0.0;
  NearestK(query, 1, &index, &squared);
  return {index, squared};
}

size_t KdTree3d::NearestK(const Eigen::Vector3d& query, size_t k, uint32_t* indices, double* squared_distances,
                          size_t num_seeds, double max_squared_distance) const {
  if (impl_->points.empty()) throw Error("KdTree3d: nearest-neighbour query on an empty tree");
  if (k == 0) return 0;
  uint32_t seeds[64];
  const size_t n = std::min({num_seeds, k, std::size(seeds)});
  std::copy(indices, indices + n, seeds);
  BoundedKnn result(k, indices, squared_distances, max_squared_distance);
  for (size_t i = 0; i < n; ++i) {
    if (seeds[i] < impl_->points.size()) result.addPoint(SquaredDistance(query, impl_->points[seeds[i]]), seeds[i]);
  }
  impl_->tree->findNeighbors(result, query.data(), nanoflann::SearchParams());
  return result.size();
}

// ---- ICP ----

namespace {

// Nearest-neighbour search limited to a radius R (the correspondence
// distance; infinite by default), with a cache that skips the tree when the
// answer provably has not changed. A full query at position a stores the K
// nearest points within R and a bound b: the K-th distance, or R when fewer
// than K points lie within R. Every point not stored was at least b from a,
// so at a later position x it is at least b - |x - a| away (triangle
// inequality). If the nearest stored point is within b - |x - a| of x, it is
// an exact nearest neighbour and the tree is not needed. Late ICP iterations
// move points by millimetres, much less than the point spacing, so most
// queries are answered from the cache, and a full query is warm-started from
// the old answer. The pairs are the same as with plain queries (up to ties
// between equidistant points); a finite R also makes far queries cheap.
class CachedNearest {
 public:
  static constexpr size_t kK = 4;
  static constexpr size_t kNone = static_cast<size_t>(-1);

  CachedNearest(const KdTree3d& tree, size_t num_queries, bool enabled, double radius_m)
      : tree_(tree),
        entries_(enabled ? num_queries : 0),
        radius_m_(radius_m),
        // nanoflann keeps points strictly nearer than the bound; one ulp more keeps distance == R.
        radius_squared_(std::nextafter(radius_m * radius_m, std::numeric_limits<double>::infinity())) {}

  // Nearest tree point to `x` (query number `i`) and its squared distance;
  // {kNone, +inf} when no point lies within R.
  std::pair<size_t, double> Find(size_t i, const Eigen::Vector3d& x) {
    if (entries_.empty()) {
      uint32_t index = 0;
      double squared = 0.0;
      if (tree_.NearestK(x, 1, &index, &squared, 0, radius_squared_) == 0) return {kNone, kInfinity};
      return {index, squared};
    }
    Entry& e = entries_[i];
    const std::vector<Eigen::Vector3d>& points = tree_.points();
    if (e.count > 0) {
      uint32_t best = e.indices[0];
      double best_squared = SquaredDistance(x, points[best]);
      for (size_t n = 1; n < e.count; ++n) {
        const double squared = SquaredDistance(x, points[e.indices[n]]);
        if (squared < best_squared) {
          best_squared = squared;
          best = e.indices[n];
        }
      }
      const double margin = e.bound - (x - e.anchor).norm();
      if (margin >= 0.0 && best_squared <= margin * margin) return {best, best_squared};
    }
    double squared[kK];
    e.count = tree_.NearestK(x, kK, e.indices.data(), squared, e.count, radius_squared_);  // warm start
    e.anchor = x;
    e.bound = e.count < kK ? radius_m_ : std::sqrt(squared[kK - 1]);
    if (e.count == 0) return {kNone, kInfinity};
    return {e.indices[0], squared[0]};
  }

 private:
  static constexpr double kInfinity = std::numeric_limits<double>::infinity();
  struct Entry {
    std::array<uint32_t, kK> indices{};
    size_t count = 0;
    Eigen::Vector3d anchor = Eigen::Vector3d::Zero();
    double bound = 0.0;
  };
  const KdTree3d& tree_;
  std::vector<Entry> entries_;
  double radius_m_;
  double radius_squared_;
};

// Pairs (model point in receiver frame, sensed point in tanker frame) of one
// iteration and the sum of their squared distances.
struct Pairs {
  std::vector<Eigen::Vector3d> model;
  std::vector<Eigen::Vector3d> sensed;
  double sum_squared = 0.0;
  size_t queries = 0;

  double Mse() const { return model.empty() ? 0.0 : sum_squared / static_cast<double>(model.size()); }
};

void CheckFinite(const std::vector<Eigen::Vector3d>& points, const char* what) {
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      throw Error(std::string("ICP: ") + what + " point " + std::to_string(i) + " is not finite");
    }
  }
}

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
  CheckFinite(model_, "model");
  if (options_.correspondence == IcpCorrespondence::kSensedToModel) {
    model_tree_ = std::make_unique<KdTree3d>(model_, options_.kdtree_leaf_size);
  }
}

IcpRegistration::~IcpRegistration() = default;

IcpResult IcpRegistration::Register(const std::vector<Eigen::Vector3d>& sensed,
                                    const Eigen::Isometry3d& initial_tanker_from_receiver) const {
  if (sensed.empty()) throw Error("ICP: the sensed point cloud is empty");
  CheckFinite(sensed, "sensed");
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

  IcpResult result;
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

IcpResult RegisterIcp(const std::vector<Eigen::Vector3d>& model_points_in_receiver,
                      const std::vector<Eigen::Vector3d>& sensed_points_in_tanker,
                      const Eigen::Isometry3d& initial_tanker_from_receiver, const IcpOptions& options) {
  return IcpRegistration(model_points_in_receiver, options)
      .Register(sensed_points_in_tanker, initial_tanker_from_receiver);
}

}  // namespace aar
