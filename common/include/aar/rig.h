#pragma once
// The stereo rig (scenes/rig.json, docs/frames.md): two pinhole cameras with
// no distortion, each with its pose tanker_from_camera.

#include <Eigen/Geometry>
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <optional>

namespace aar {

struct Intrinsics {
  int width_px = 1024;   ///< image width [px]
  int height_px = 768;   ///< image height [px]
  double fx_px = 900.0;  ///< focal length along x [px]
  double fy_px = 900.0;  ///< focal length along y [px]
  double cx_px = 511.5;  ///< principal point x [px], OpenCV convention (pixel centres at integers)
  double cy_px = 383.5;  ///< principal point y [px]

  Eigen::Matrix3d CameraMatrix() const;
  /// Pixel of a point in the camera frame (x right, y down, z forward); nullopt behind the camera.
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& point_in_cam) const;
  bool Contains(const Eigen::Vector2d& pixel) const;
};

struct Camera {
  Intrinsics intrinsics;
  Eigen::Isometry3d tanker_from_camera = Eigen::Isometry3d::Identity();
};

struct StereoRig {
  Camera left;
  Camera right;
  double near_m = 0.5;                                           ///< near clip plane [m]
  Eigen::Vector3d contact_position_m = Eigen::Vector3d::Zero();  ///< receiver contact position in the tanker frame [m]

  /// right_from_left: OpenCV stereoCalibrate's (R, T).
  Eigen::Isometry3d RightFromLeft() const;
  /// Distance between the camera centres [m].
  double Baseline() const;
};

/// Reads a rig file; throws aar::Error naming the file and the bad field.
StereoRig LoadRig(const std::filesystem::path& path);

/// JSON form used in rig files and frame sidecars.
nlohmann::json IntrinsicsToJson(const Intrinsics& intrinsics);
nlohmann::json IsometryToJson(const Eigen::Isometry3d& a_from_b);
nlohmann::json RigToJson(const StereoRig& rig);
/// Parse helpers; `where` prefixes error messages.
Intrinsics IntrinsicsFromJson(const nlohmann::json& j, int width, int height, const std::string& where);
Eigen::Isometry3d IsometryFromJson(const nlohmann::json& j, const std::string& where);
StereoRig RigFromJson(const nlohmann::json& j, const std::string& where);

}  // namespace aar
