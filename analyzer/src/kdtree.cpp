#include "aar/analyzer/kdtree.h"

#include <algorithm>
#include <iterator>
#include <nanoflann.hpp>

#include "aar/error.h"

namespace aar {

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

using NanoflannTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>,
                                                          PointsAdaptor, 3, uint32_t>;

}  // namespace

struct KdTree3d::Impl {
  std::vector<Eigen::Vector3d> points;
  PointsAdaptor adaptor;
  std::unique_ptr<NanoflannTree> tree;
};

void CheckFinitePoints(const std::vector<Eigen::Vector3d>& points, const std::string& what) {
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) throw Error(what + " " + std::to_string(i) + " is not finite");
  }
}

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
  BoundedKnn result(k, indices, squared_distances, max_squared_distance);
  result.addSeeds(query, impl_->points, num_seeds);
  impl_->tree->findNeighbors(result, query.data(), nanoflann::SearchParams());
  return result.size();
}

}  // namespace aar
