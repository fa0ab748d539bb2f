#pragma once
// Nearest-neighbour queries of points that move a little between calls (ICP
// iterations), answered from a per-query cache when provably unchanged.
//
// A full query at position a stores the K nearest tree points within a radius
// R and a bound b: the K-th distance, or R when fewer than K points lie within
// R. Every point not stored was at least b from a, so at a later position x it
// is at least b - |x - a| away (triangle inequality). If the nearest stored
// point is within b - |x - a| of x, it is an exact nearest neighbour and the
// tree is not needed. Late ICP iterations move points by millimetres, much
// less than the point spacing, so most queries are answered from the cache,
// and a full query is warm-started from the old answer. The answers are those
// of plain queries (up to ties between equidistant points); a finite R also
// makes far queries cheap.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "aar/analyzer/kdtree.h"  // SquaredDistance
#include "aar/analyzer/nearest_search.h"

namespace aar {

class CachedNearest {
 public:
  static constexpr size_t kK = 4;  ///< neighbours stored per query
  static constexpr size_t kNone = static_cast<size_t>(-1);

  /// `num_queries` query slots over `tree` (which must outlive this object);
  /// `enabled` = false answers every query from the tree; `radius_m` = R [m].
  CachedNearest(const NearestSearch3d& tree, size_t num_queries, bool enabled, double radius_m);

  /// Nearest tree point to `x` (query slot `i`) and its squared distance;
  /// {kNone, +inf} when no point lies within R.
  std::pair<size_t, double> Find(size_t i, const Eigen::Vector3d& x);

 private:
  struct Entry {
    std::array<uint32_t, kK> indices{};
    size_t count = 0;
    Eigen::Vector3d anchor = Eigen::Vector3d::Zero();
    double bound = 0.0;
  };
  const NearestSearch3d& tree_;
  std::vector<Entry> entries_;
  double radius_m_;
  double radius_squared_;
};

}  // namespace aar
