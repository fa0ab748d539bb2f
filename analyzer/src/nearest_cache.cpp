#include "aar/analyzer/nearest_cache.h"

#include <cmath>

namespace aar {
namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}  // namespace

CachedNearest::CachedNearest(const NearestSearch3d& tree, size_t num_queries, bool enabled, double radius_m)
    : tree_(tree),
      entries_(enabled ? num_queries : 0),
      radius_m_(radius_m),
      // nanoflann keeps points strictly nearer than the bound; one ulp more keeps distance == R.
      radius_squared_(std::nextafter(radius_m * radius_m, kInfinity)) {}

std::pair<size_t, double> CachedNearest::Find(size_t i, const Eigen::Vector3d& x) {
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

}  // namespace aar
