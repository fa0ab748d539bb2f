#include "aar/analyzer/sheet_grid.h"

#include <algorithm>
#include <cmath>

#include "aar/analyzer/kdtree.h"  // CheckFinitePoints
#include "aar/error.h"

namespace aar {
namespace {
// At most this many cells per point (a few points spread over a large box).
constexpr double kMaxCellsPerPoint = 4.0;
}  // namespace

SheetGrid3d::SheetGrid3d(std::vector<Eigen::Vector3d> points, double cell_scale) : points_(std::move(points)) {
  if (points_.empty()) throw Error("SheetGrid3d: no points");
  if (points_.size() > static_cast<size_t>(UINT32_MAX)) throw Error("SheetGrid3d: too many points");
  if (!(cell_scale > 0.0) || !std::isfinite(cell_scale)) throw Error("SheetGrid3d: cell_scale must be finite and > 0");
  CheckFinitePoints(points_, "SheetGrid3d: point");
  double x1 = points_[0].x(), y1 = points_[0].y();
  x0_ = x1;
  y0_ = y1;
  for (const Eigen::Vector3d& p : points_) {
    x0_ = std::min(x0_, p.x());
    y0_ = std::min(y0_, p.y());
    x1 = std::max(x1, p.x());
    y1 = std::max(y1, p.y());
  }
  const double n = static_cast<double>(points_.size());
  const double width = x1 - x0_, height = y1 - y0_;
  cell_ = cell_scale * std::sqrt(width * height / n);
  // Thin or degenerate boxes: no more than kMaxCellsPerPoint cells per point along the long side squared.
  cell_ = std::max({cell_, std::max(width, height) / (kMaxCellsPerPoint * n), 1e-12});
  nx_ = static_cast<long>(width / cell_) + 1;
  ny_ = static_cast<long>(height / cell_) + 1;
  while (static_cast<double>(nx_) * static_cast<double>(ny_) > kMaxCellsPerPoint * n + 1.0) {
    cell_ *= 1.5;
    nx_ = static_cast<long>(width / cell_) + 1;
    ny_ = static_cast<long>(height / cell_) + 1;
  }
  const auto cell_of = [&](const Eigen::Vector3d& p) {
    const long cx = std::min(nx_ - 1, static_cast<long>((p.x() - x0_) / cell_));
    const long cy = std::min(ny_ - 1, static_cast<long>((p.y() - y0_) / cell_));
    return static_cast<size_t>(cy * nx_ + cx);
  };
  // Counting sort by cell; within a cell the indices stay ascending.
  cell_start_.assign(static_cast<size_t>(nx_ * ny_) + 1, 0);
  for (const Eigen::Vector3d& p : points_) ++cell_start_[cell_of(p) + 1];
  for (size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  order_.resize(points_.size());
  std::vector<uint32_t> next(cell_start_.begin(), cell_start_.end() - 1);
  for (size_t i = 0; i < points_.size(); ++i) order_[next[cell_of(points_[i])]++] = static_cast<uint32_t>(i);
}

size_t SheetGrid3d::NearestK(const Eigen::Vector3d& query, size_t k, uint32_t* indices, double* squared_distances,
                             size_t num_seeds, double max_squared_distance) const {
  if (k == 0) return 0;
  BoundedKnn result(k, indices, squared_distances, max_squared_distance);
  result.addSeeds(query, points_, num_seeds);
  // The query's cell, possibly outside the grid (then its rings start where they reach it).
  const double fx = std::floor((query.x() - x0_) / cell_), fy = std::floor((query.y() - y0_) / cell_);
  const double far = 4.0 * static_cast<double>(std::max(nx_, ny_)) + 4.0;  // keeps the longs in range
  const long cx = static_cast<long>(std::clamp(fx, -far, far)), cy = static_cast<long>(std::clamp(fy, -far, far));
  // Distance across (x, y) from the query to the edge of its cell's block of radius r - 1,
  // below which every point of ring r lies: the block's half side minus the query's offset from its centre.
  const double ox = query.x() - (x0_ + (static_cast<double>(cx) + 0.5) * cell_);
  const double oy = query.y() - (y0_ + (static_cast<double>(cy) + 0.5) * cell_);
  const double offset = std::max(std::abs(ox), std::abs(oy));
  const long first = std::max({0L, -cx, cx - (nx_ - 1), -cy, cy - (ny_ - 1)});
  const long last = std::max({cx, nx_ - 1 - cx, cy, ny_ - 1 - cy});  // the ring that reaches the far corner
  const auto visit_cell = [&](long x, long y) {
    const size_t c = static_cast<size_t>(y * nx_ + x);
    for (uint32_t m = cell_start_[c]; m < cell_start_[c + 1]; ++m) {
      const uint32_t i = order_[m];
      result.addPoint(SquaredDistance(query, points_[i]), i);
    }
  };
  for (long r = first; r <= last; ++r) {
    if (r > 0) {
      const double gap = (static_cast<double>(r) - 0.5) * cell_ - offset;
      if (gap > 0.0 && gap * gap >= result.worstDist()) break;
    }
    const long x_lo = std::max(0L, cx - r), x_hi = std::min(nx_ - 1, cx + r);
    const long y_lo = std::max(0L, cy - r), y_hi = std::min(ny_ - 1, cy + r);
    if (r == 0) {
      visit_cell(cx, cy);
      continue;
    }
    if (cy - r >= 0) {
      for (long x = x_lo; x <= x_hi; ++x) visit_cell(x, cy - r);
    }
    if (cy + r < ny_) {
      for (long x = x_lo; x <= x_hi; ++x) visit_cell(x, cy + r);
    }
    const long side_lo = std::max(y_lo, cy - r + 1), side_hi = std::min(y_hi, cy + r - 1);
    if (cx - r >= 0) {
      for (long y = side_lo; y <= side_hi; ++y) visit_cell(cx - r, y);
    }
    if (cx + r < nx_) {
      for (long y = side_lo; y <= side_hi; ++y) visit_cell(cx + r, y);
    }
  }
  return result.size();
}

}  // namespace aar
