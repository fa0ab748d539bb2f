#include "aar/renderer/calib_poses.h"

#include <optional>

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
  // The board at `tilt` with its centre at (shift, distance) in the left camera frame, when its outline fits both
  // images. Board axes follow the camera's (x right, y down, z away), then tilt.
  const auto fitting = [&](const Tilt& tilt, double shift_x_m, double shift_y_m,
                           double distance) -> std::optional<Eigen::Isometry3d> {
    const Eigen::Matrix3d left_from_board_rotation =
        RotationFromRollPitchYaw(tilt.about_x_deg, tilt.about_y_deg, tilt.about_z_deg);
    Eigen::Isometry3d left_from_board = Eigen::Isometry3d::Identity();
    left_from_board.linear() = left_from_board_rotation;
    left_from_board.translation() =
        Eigen::Vector3d(shift_x_m, shift_y_m, distance) - left_from_board_rotation * centre_in_board;
    const Eigen::Isometry3d tanker_from_board = rig.left.tanker_from_camera * left_from_board;
    for (const Eigen::Vector3d& corner : outline) {
      const Eigen::Vector3d p = tanker_from_board * corner;
      if (!InsideWithMargin(rig.left, p, options.margin_px) || !InsideWithMargin(rig.right, p, options.margin_px)) {
        return std::nullopt;
      }
    }
    return tanker_from_board;
  };
  const auto place = [&](const Tilt& tilt, double first_m, double last_m) {
    for (double distance = first_m; distance <= last_m; distance += 0.25) {
      if (const auto tanker_from_board = fitting(tilt, tilt.shift_x_m, tilt.shift_y_m, distance)) {
        poses.push_back(PoseFromIsometry(*tanker_from_board));
        return;
      }
    }
    throw Error("calibration board does not fit both views for a tilt; check the rig");
  };
  for (const Tilt& tilt : kTilts) place(tilt, options.min_distance_m, options.min_distance_m + 39.75);
  for (const double far_m : options.far_distances_m) {
    for (const Tilt& tilt : kTilts) place(tilt, far_m, far_m);  // that distance only
  }
  if (options.corner_boards) {
    // Towards each image corner and edge: the nearest distance where the board fits, tilted 10 deg to face
    // the optical axis, then pushed across it in 5 cm steps as far as both views allow.
    static const int kDirections[8][2] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}, {-1, 0}, {1, 0}, {0, -1}, {0, 1}};
    for (const auto& d : kDirections) {
      const Tilt tilt{-10.0 * d[1], 10.0 * d[0], 0, 0, 0};
      bool placed = false;
      for (double distance = options.min_distance_m; distance <= options.min_distance_m + 39.75 && !placed;
           distance += 0.25) {
        std::optional<Eigen::Isometry3d> best;
        for (double shift = 0.0;; shift += 0.05) {
          const auto pose = fitting(tilt, d[0] * shift, d[1] * shift, distance);
          if (!pose) break;
          best = pose;
        }
        if (best) {
          poses.push_back(PoseFromIsometry(*best));
          placed = true;
        }
      }
      if (!placed) throw Error("calibration board does not fit both views towards an image corner; check the rig");
    }
  }
  return poses;
}

}  // namespace aar
