#pragma once
// The k-nearest query that ICP's neighbour cache (nearest_cache.h) needs,
// and the result set its implementations share.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace aar {

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
