#pragma once
// The k-nearest query that ICP's neighbour cache (nearest_cache.h) needs,
// and the result set its implementations share.

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <vector>

namespace aar {

/// |a - b|^2 summed in nanoflann's order (L2_Simple_Adaptor::evalMetric), so
/// distances computed with it and inside the KD-tree are bitwise equal.
inline double SquaredDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  double result = 0.0;
  for (Eigen::Index i = 0; i < 3; ++i) {
    const double diff = a[i] - b[i];
    result += diff * diff;
  }
  return result;
}

/// Exact k-nearest search over a fixed 3-D point set (L2).
class NearestSearch3d {
 public:
  virtual ~NearestSearch3d() = default;
  virtual const std::vector<Eigen::Vector3d>& points() const = 0;
  /// The k nearest points (exact) strictly nearer than sqrt(max_squared_distance),
  /// nearest first: fills indices[0..n) and squared_distances[0..n) and
  /// returns n <= k. On entry, indices[0..num_seeds) may hold point indices
  /// near the query (e.g. the previous answer of a point that moved a little);
  /// they only bound the search from the start and make it faster.
  virtual size_t NearestK(const Eigen::Vector3d& query, size_t k, uint32_t* indices, double* squared_distances,
                          size_t num_seeds = 0,
                          double max_squared_distance = std::numeric_limits<double>::infinity()) const = 0;
};

/// k-nearest result set (also nanoflann's RESULTSET interface) that can be
/// seeded with candidate points before the search, so that their distances
/// bound the search from the start, and that ignores points at or beyond a
/// radius. Points already held are not added twice (a seed met again).
class BoundedKnn {
 public:
  BoundedKnn(size_t capacity, uint32_t* indices, double* squared, double max_squared)
      : capacity_(capacity), indices_(indices), squared_(squared), max_squared_(max_squared) {}
  size_t size() const { return count_; }
  bool full() const { return count_ == capacity_; }
  /// Squared distance a point must be strictly below to enter.
  double worstDist() const { return count_ < capacity_ ? max_squared_ : squared_[capacity_ - 1]; }
  /// Adds the seeds a caller of NearestK left in the first `num_seeds` (at
  /// most the capacity) result slots, skipping indices outside `points`;
  /// the search then overwrites those slots.
  void addSeeds(const Eigen::Vector3d& query, const std::vector<Eigen::Vector3d>& points, size_t num_seeds) {
    uint32_t seeds[64];
    const size_t n = std::min({num_seeds, capacity_, std::size(seeds)});
    std::copy(indices_, indices_ + n, seeds);
    for (size_t i = 0; i < n; ++i) {
      if (seeds[i] < points.size()) addPoint(SquaredDistance(query, points[seeds[i]]), seeds[i]);
    }
  }
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

}  // namespace aar
