#include "aar/analyzer/pose_filter.h"

#include <Eigen/Geometry>
#include <cstddef>

namespace aar {
namespace {

// Times closer than this count as equal: the CSVs keep 6 decimals of a second.
constexpr double kTimeToleranceS = 1e-9;
constexpr size_t kMinFitPoses = 3;  // two poses fit a line exactly: nothing to smooth

Eigen::Vector3d RotationLog(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd angle_axis(rotation);
  return angle_axis.angle() * angle_axis.axis();
}

Eigen::Matrix3d RotationExp(const Eigen::Vector3d& log) {
  const double angle = log.norm();
  if (angle == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, log / angle).toRotationMatrix();
}

// The value at offset 0 of the least-squares line through (offsets[i], values[i]).
Eigen::Vector3d LineAtZero(const std::vector<double>& offsets, const std::vector<Eigen::Vector3d>& values) {
  const double n = static_cast<double>(offsets.size());
  double mean_offset = 0.0;
  Eigen::Vector3d mean_value = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < offsets.size(); ++i) {
    mean_offset += offsets[i];
    mean_value += values[i];
  }
  mean_offset /= n;
  mean_value /= n;
  double spread = 0.0;
  Eigen::Vector3d covariance = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < offsets.size(); ++i) {
    const double d = offsets[i] - mean_offset;
    spread += d * d;
    covariance += d * (values[i] - mean_value);
  }
  const Eigen::Vector3d slope = covariance / spread;
  return mean_value - slope * mean_offset;
}

}  // namespace

std::vector<std::optional<Pose>> FilterPoses(const std::vector<TimedPose>& frames, const PoseFilterOptions& options) {
  std::vector<std::optional<Pose>> filtered(frames.size());
  size_t chain_begin = 0;  // first frame of the current run of estimates with increasing times
  for (size_t k = 0; k < frames.size(); ++k) {
    if (!frames[k].pose) {
      chain_begin = k + 1;
      continue;
    }
    if (k > chain_begin && !(frames[k].time_s > frames[k - 1].time_s + kTimeToleranceS)) chain_begin = k;
    size_t first = k;
    while (first > chain_begin && frames[k].time_s - frames[first - 1].time_s <= options.window_s + kTimeToleranceS) {
      --first;
    }
    if (k + 1 - first < kMinFitPoses) {
      filtered[k] = frames[k].pose;
      continue;
    }
    const Eigen::Isometry3d newest = IsometryFromPose(*frames[k].pose);
    std::vector<double> offsets;
    std::vector<Eigen::Vector3d> positions, rotations;
    for (size_t j = first; j <= k; ++j) {
      const Eigen::Isometry3d pose = IsometryFromPose(*frames[j].pose);
      offsets.push_back(frames[j].time_s - frames[k].time_s);
      positions.push_back(pose.translation());
      rotations.push_back(RotationLog(newest.linear().transpose() * pose.linear()));
    }
    Eigen::Isometry3d fitted = Eigen::Isometry3d::Identity();
    fitted.translation() = LineAtZero(offsets, positions);
    fitted.linear() = newest.linear() * RotationExp(LineAtZero(offsets, rotations));
    filtered[k] = PoseFromIsometry(fitted);
  }
  return filtered;
}

}  // namespace aar
