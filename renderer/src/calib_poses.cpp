#include "aar/renderer/calib_poses.h"

#include "aar/error.h"
#include "aar/text.h"

namespace aar {
namespace {

bool InsideWithMargin(const Camera& camera, const Eigen::Vector3d& point_in_tanker, double margin) {
  const auto pixel = camera.intrinsics.Project(camera.tanker_from_camera.inverse() * point_in_tanker);
  return pixel && pixel->x() >= margin && pixel->y() >= margin &&
         pixel->x() <= camera.intrinsics.width_px - 1 - margin &&
         pixel->y() <= camera.intrinsics.height_px - 1 - margin;
}

}  // namespace

std::vector<Eigen::Vector3d> BoardOutline(const CalibPoseOptions& o) {
  // Squares extend one square beyond the inner corners on every side, then the border.
  const double pad = o.board.square_m + o.border_m;
  const double x1 = (o.board.inner_corners_x - 1) * o.board.square_m + pad;
  const double y1 = (o.board.inner_corners_y - 1) * o.board.square_m + pad;
  return {{-pad, -pad, 0}, {x1, -pad, 0}, {x1, y1, 0}, {-pad, y1, 0}};
}

std::vector<Pose> CalibrationBoardPoses(const StereoRig& rig, const CalibPoseOptions& options) {
  struct Tilt {
    double about_x_deg, about_y_deg, about_z_deg;  // board rotation in the left camera frame
    double shift_x_m, shift_y_m;                   // board-centre offset across the optical axis
  };
  static const Tilt kTilts[] = {
      {0, 0, 4, 0.13, 0.07},     {25, 0, 0, 0, 0.5},    {-25, 0, 0, 0, -0.5},     {0, 25, 0, 0.5, 0},
      {0, -25, 0, -0.5, 0},      {20, 20, 5, 0.5, 0.5}, {-20, 20, -5, 0.5, -0.5}, {20, -20, -5, -0.5, 0.5},
      {-20, -20, 5, -0.5, -0.5}, {10, -10, 15, 0, 0},   {-10, 10, -15, 0, 0},     {30, 15, 0, 0.3, 0.3},
  };
  const std::vector<Eigen::Vector3d> outline = BoardOutline(options);
  const Eigen::Vector3d centre_in_board((options.board.inner_corners_x - 1) * options.board.square_m / 2.0,
                                        (options.board.inner_corners_y - 1) * options.board.square_m / 2.0, 0.0);
  for (const double far_m : options.far_distances_m) {
    if (!(far_m >= options.min_distance_m && far_m <= 1000.0)) {
      throw Error("calibration boards: a far distance must be in " + FormatFixed(options.min_distance_m, 1) +
                  "..1000 m, got " + FormatFixed(far_m, 3));
    }
  }
  std::vector<Pose> poses;
  const auto place = [&](const Tilt& tilt, double first_m, double last_m) {
    // Board axes follow the camera's (x right, y down, z away), then tilt.
    const Eigen::Matrix3d left_from_board_rotation =
        RotationFromRollPitchYaw(tilt.about_x_deg, tilt.about_y_deg, tilt.about_z_deg);
    bool placed = false;
    for (double distance = first_m; distance <= last_m && !placed; distance += 0.25) {
      Eigen::Isometry3d left_from_board = Eigen::Isometry3d::Identity();
      left_from_board.linear() = left_from_board_rotation;
      left_from_board.translation() =
          Eigen::Vector3d(tilt.shift_x_m, tilt.shift_y_m, distance) - left_from_board_rotation * centre_in_board;
      const Eigen::Isometry3d tanker_from_board = rig.left.tanker_from_camera * left_from_board;
      bool fits = true;
      for (const Eigen::Vector3d& corner : outline) {
        const Eigen::Vector3d p = tanker_from_board * corner;
        fits = fits && InsideWithMargin(rig.left, p, options.margin_px) &&
               InsideWithMargin(rig.right, p, options.margin_px);
      }
      if (fits) {
        poses.push_back(PoseFromIsometry(tanker_from_board));
        placed = true;
      }
    }
    if (!placed) throw Error("calibration board does not fit both views for a tilt; check the rig");
  };
  for (const Tilt& tilt : kTilts) place(tilt, options.min_distance_m, options.min_distance_m + 39.75);
  for (const double far_m : options.far_distances_m) {
    for (const Tilt& tilt : kTilts) place(tilt, far_m, far_m);  // that distance only
  }
  return poses;
}

}  // namespace aar
