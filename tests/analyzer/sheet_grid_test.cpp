// SheetGrid3d against the KD-tree: the same k nearest points, inside and
// outside the grid, with seeds and radii.
#include "aar/analyzer/sheet_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "aar/analyzer/kdtree.h"
#include "aar/error.h"

namespace aar {
namespace {

// Three overlapping layers across (x, y) at different z, as the surfaces of a
// receiver facing a camera look in its disparity space, plus a few strays.
std::vector<Eigen::Vector3d> Sheet(std::mt19937_64& rng, size_t n) {
  std::uniform_real_distribution<double> x(-400.0, 400.0), y(-150.0, 150.0), jitter(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (size_t i = 0; i < n; ++i) {
    const double layer = static_cast<double>(i % 3) * 12.0;
    const double px = x(rng), py = i % 3 == 2 ? 0.2 * y(rng) : y(rng);  // a narrow third layer (a wing)
    points.emplace_back(px, py, 200.0 + layer + 0.02 * px + jitter(rng));
  }
  points.emplace_back(900.0, 900.0, 0.0);
  points.emplace_back(-900.0, 10.0, 500.0);
  return points;
}

TEST(SheetGrid, SameNeighboursAsTheKdTree) {
  std::mt19937_64 rng(7);
  const std::vector<Eigen::Vector3d> points = Sheet(rng, 6000);
  const KdTree3d tree(points);
  for (const double cell_scale : {0.3, 1.0, 5.0}) {
    const SheetGrid3d grid(points, cell_scale);
    std::uniform_real_distribution<double> qx(-1200.0, 1200.0), qy(-600.0, 600.0), qz(150.0, 260.0);
    for (int q = 0; q < 2000; ++q) {
      const Eigen::Vector3d query(qx(rng), qy(rng), qz(rng));
      for (const size_t k : {size_t{1}, size_t{4}}) {
        for (const double radius : {std::numeric_limits<double>::infinity(), 30.0}) {
          uint32_t want[4], got[4];
          double want_d[4], got_d[4];
          const size_t n_want = tree.NearestK(query, k, want, want_d, 0, radius * radius);
          // Seed the grid with a far point, as a cache would after a long move.
          got[0] = static_cast<uint32_t>(q % points.size());
          const size_t n_got = grid.NearestK(query, k, got, got_d, 1, radius * radius);
          ASSERT_EQ(n_got, n_want) << "query " << q << " k " << k << " scale " << cell_scale;
          for (size_t i = 0; i < n_got; ++i) {
            EXPECT_EQ(got[i], want[i]) << "query " << q << " neighbour " << i;
            EXPECT_EQ(got_d[i], want_d[i]);
          }
        }
      }
    }
  }
}

TEST(SheetGrid, DegenerateSetsAndBadInput) {
  // All points on one vertical line: one cell.
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 50; ++i) line.emplace_back(1.0, 2.0, static_cast<double>(i));
  const SheetGrid3d grid(line);
  uint32_t index[2];
  double squared[2];
  ASSERT_EQ(grid.NearestK(Eigen::Vector3d(5.0, 2.0, 10.2), 2, index, squared), 2u);
  EXPECT_EQ(index[0], 10u);
  EXPECT_EQ(index[1], 11u);
  EXPECT_DOUBLE_EQ(squared[0], 16.0 + 0.04);
  EXPECT_THROW(SheetGrid3d(std::vector<Eigen::Vector3d>{}), Error);
  EXPECT_THROW(SheetGrid3d(line, 0.0), Error);
  line.emplace_back(std::nan(""), 0.0, 0.0);
  EXPECT_THROW(SheetGrid3d{line}, Error);
}

}  // namespace
}  // namespace aar
