#include "receiver_box.h"

#include <algorithm>
#include <limits>
#include <optional>

namespace aar::flightpaths {
namespace {

/// Pixel margin of one point in one camera: distance to the nearest image
/// border (negative outside); -1e9 behind the camera.
double PixelMargin(const Camera& camera, const Eigen::Vector3d& point_in_tanker, bool* inside) {
  const Eigen::Vector3d in_cam = camera.tanker_from_camera.inverse() * point_in_tanker;
  const std::optional<Eigen::Vector2d> pixel = camera.intrinsics.Project(in_cam);
  if (!pixel) {
    *inside = false;
    return -1e9;
  }
  *inside = camera.intrinsics.Contains(*pixel);
  const Intrinsics& k = camera.intrinsics;
  return std::min({pixel->x() + 0.5, pixel->y() + 0.5, k.width_px - 0.5 - pixel->x(), k.height_px - 0.5 - pixel->y()});
}

}  // namespace

std::vector<Eigen::Vector3d> ReceiverBox::Corners() const {
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) {
    corners.emplace_back((i & 1) ? max_m.x() : min_m.x(), (i & 2) ? max_m.y() : min_m.y(),
                         (i & 4) ? max_m.z() : min_m.z());
  }
  return corners;
}

BoxVisibility ComputeBoxVisibility(const StereoRig& rig, const ReceiverBox& box, const Pose& tanker_from_receiver) {
  const Eigen::Isometry3d pose = IsometryFromPose(tanker_from_receiver);
  BoxVisibility vis;
  vis.min_margin_px = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& corner : box.Corners()) {
    const Eigen::Vector3d p = pose * corner;
    bool in_left = false;
    bool in_right = false;
    vis.min_margin_px = std::min(vis.min_margin_px, PixelMargin(rig.left, p, &in_left));
    vis.min_margin_px = std::min(vis.min_margin_px, PixelMargin(rig.right, p, &in_right));
    vis.corners_in_left += in_left ? 1 : 0;
    vis.corners_in_right += in_right ? 1 : 0;
  }
  bool ref_left = false;
  bool ref_right = false;
  PixelMargin(rig.left, tanker_from_receiver.translation_m, &ref_left);
  PixelMargin(rig.right, tanker_from_receiver.translation_m, &ref_right);
  vis.reference_in_both = ref_left && ref_right;
  return vis;
}

double RangeFromLeftCamera(const StereoRig& rig, const Pose& tanker_from_receiver) {
  return (tanker_from_receiver.translation_m - rig.left.tanker_from_camera.translation()).norm();
}

}  // namespace aar::flightpaths
