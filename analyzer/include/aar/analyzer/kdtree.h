#pragma once
// Exact nearest-neighbour search over a fixed 3-D point set (nanoflann
// KD-tree, L2), with seeded k-nearest queries for warm starts.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "aar/analyzer/nearest_search.h"

namespace aar {

/// 3-D KD-tree (nanoflann, L2) over a point set it owns. Queries are const
/// and may run from several threads at once.
class KdTree3d : public NearestSearch3d {
 public:
  explicit KdTree3d(std::vector<Eigen::Vector3d> points, int leaf_size = 10);
  ~KdTree3d() override;
  KdTree3d(KdTree3d&&) noexcept;
  KdTree3d& operator=(KdTree3d&&) noexcept;
  KdTree3d(const KdTree3d&) = delete;
  KdTree3d& operator=(const KdTree3d&) = delete;

  const std::vector<Eigen::Vector3d>& points() const override;
  /// Index and squared distance of the nearest point (exact); the tree must not be empty.
  std::pair<size_t, double> Nearest(const Eigen::Vector3d& query) const;
  /// See NearestSearch3d::NearestK.
  size_t NearestK(const Eigen::Vector3d& query, size_t k, uint32_t* indices, double* squared_distances,
                  size_t num_seeds = 0,
                  double max_squared_distance = std::numeric_limits<double>::infinity()) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Throws aar::Error "`what` I is not finite" for the first point with a NaN
/// or infinite coordinate.
void CheckFinitePoints(const std::vector<Eigen::Vector3d>& points, const std::string& what);

}  // namespace aar
