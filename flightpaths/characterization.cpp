#include "characterization.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "aar/error.h"

namespace aar::flightpaths {
namespace {

/// Grid fractions in [-1, 1] x [-1, 1] (image x right, y down), row-major.
std::vector<Eigen::Vector2d> GridFractions(const CharacterizationOptions& o) {
  std::vector<Eigen::Vector2d> grid;
  auto fraction = [](int i, int n) { return n == 1 ? 0.0 : -1.0 + 2.0 * i / (n - 1); };
  for (int row = 0; row < o.grid_rows; ++row) {
    for (int col = 0; col < o.grid_columns; ++col) {
      const bool corner = (row == 0 || row == o.grid_rows - 1) && (col == 0 || col == o.grid_columns - 1);
      if (corner && o.drop_grid_corners && o.grid_rows > 1 && o.grid_columns > 1) continue;
      grid.emplace_back(fraction(col, o.grid_columns), fraction(row, o.grid_rows));
    }
  }
  return grid;
}

/// Where the characterization grid is centred at range r: the reference
/// point such that the box centre (zero attitude) lies on the line through
/// the midpoint of the two camera centres along the left optical axis.
/// Returned in the left camera frame.
Eigen::Vector3d BoxCentredPoint(const StereoRig& rig, const ReceiverBox& box, double range_m) {
  const Eigen::Isometry3d left_from_tanker = rig.left.tanker_from_camera.inverse();
  const Eigen::Vector3d midpoint =
      left_from_tanker *
      (0.5 * (rig.left.tanker_from_camera.translation() + rig.right.tanker_from_camera.translation()));
  const Eigen::Vector3d centre_offset = left_from_tanker.linear() * box.Centre();
  const Eigen::Vector3d w = midpoint - centre_offset;
  const double disc = w.z() * w.z() - w.squaredNorm() + range_m * range_m;
  const double t = -w.z() + std::sqrt(std::max(disc, 0.0));
  return w + t * Eigen::Vector3d::UnitZ();
}

Pose PoseFromLeftPoint(const StereoRig& rig, const Eigen::Vector3d& point_in_left) {
  Pose pose;
  pose.translation_m = rig.left.tanker_from_camera * point_in_left;
  return pose;
}

bool BoxFits(const StereoRig& rig, const ReceiverBox& box, const Pose& pose, double margin_px) {
  const BoxVisibility vis = ComputeBoxVisibility(rig, box, pose);
  return vis.FullyInBoth() && vis.min_margin_px >= margin_px;
}

}  // namespace

void CharacterizationOptions::Check() const {
  if (grid_columns < 1 || grid_rows < 1) throw Error("characterization options: grid must be at least 1 x 1");
  if (!(min_range_m > 0.0) || !(max_range_m > min_range_m)) {
    throw Error("characterization options: need 0 < min_range_m < max_range_m");
  }
  if (!(partial_view_spread >= 0.0 && partial_view_spread <= 1.0)) {
    throw Error("characterization options: partial_view_spread must be in [0, 1]");
  }
  const size_t per_shell = GridFractions(*this).size();
  if (range_shells == 0 || range_shells * per_shell != count) {
    throw Error("characterization options: range_shells (" + std::to_string(range_shells) + ") x grid points (" +
                std::to_string(per_shell) + ") must equal count (" + std::to_string(count) + ")");
  }
  if (std::gcd(range_scramble, per_shell) != 1) {
    throw Error("characterization options: range_scramble must be coprime to the number of grid points");
  }
}

double MinimumFitRange(const StereoRig& rig, const ReceiverBox& box, double margin_px) {
  auto fits = [&](double r) {
    return BoxFits(rig, box, PoseFromLeftPoint(rig, BoxCentredPoint(rig, box, r)), margin_px);
  };
  double lo = 1.0;
  double hi = 1000.0;
  if (!fits(hi)) return std::numeric_limits<double>::infinity();
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (fits(mid) ? hi : lo) = mid;
  }
  return hi;
}

std::vector<FlightSample> GenerateCharacterization(const StereoRig& rig, const CharacterizationOptions& o,
                                                   const ReceiverBox& box) {
  o.Check();
  const std::vector<Eigen::Vector2d> grid = GridFractions(o);
  const size_t per_shell = grid.size();

  const Intrinsics& k = rig.left.intrinsics;
  const double half_x = 0.5 * k.width_px / k.fx_px;  // half field of view, normalized image units
  const double half_y = 0.5 * k.height_px / k.fy_px;

  std::vector<FlightSample> samples(o.count);
  for (size_t shell = 0; shell < o.range_shells; ++shell) {
    for (size_t g = 0; g < per_shell; ++g) {
      const size_t index = shell * per_shell + (g * o.range_scramble) % per_shell;
      const double r = o.min_range_m + (o.max_range_m - o.min_range_m) * (static_cast<double>(index) + 0.5) /
                                           static_cast<double>(o.count);
      const Eigen::Vector3d centred = BoxCentredPoint(rig, box, r);
      const Eigen::Vector2d origin(centred.x() / centred.z(), centred.y() / centred.z());
      const Eigen::Vector2d cell = grid[g];
      const double ring = std::max(std::abs(cell.x()), std::abs(cell.y()));  // 0 centre .. 1 grid border
      Eigen::Vector2d edge = Eigen::Vector2d::Zero();                        // grid border point on this ray
      if (ring > 0.0) edge = Eigen::Vector2d(cell.x() / ring * half_x, cell.y() / ring * half_y);
      auto point_at = [&](double lambda) {
        const Eigen::Vector2d ab = origin + lambda * edge;
        return Eigen::Vector3d(r * Eigen::Vector3d(ab.x(), ab.y(), 1.0).normalized());
      };
      auto fits = [&](double lambda) {
        return BoxFits(rig, box, PoseFromLeftPoint(rig, point_at(lambda)), o.edge_margin_px);
      };
      // Largest lambda along the ray for which the box still fits; the grid
      // point goes to `ring` of it, so the points stay evenly spaced.
      double lambda_edge = o.partial_view_spread;
      if (fits(0.0)) {
        double lo = 0.0;
        double hi = 1.0;
        if (fits(hi)) {
          lo = hi;
        } else {
          for (int i = 0; i < 50; ++i) {
            const double mid = 0.5 * (lo + hi);
            (fits(mid) ? lo : hi) = mid;
          }
        }
        lambda_edge = lo;
      }
      FlightSample s;
      s.time_s = static_cast<double>(index);
      s.tanker_from_receiver = PoseFromLeftPoint(rig, point_at(ring * lambda_edge));
      samples[index] = RoundToCsvPrecision(s);
    }
  }
  return samples;
}

}  // namespace aar::flightpaths
