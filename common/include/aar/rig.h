#pragma once
// The stereo rig (scenes/rig.json, docs/frames.md): two cameras, pinhole with
// optional Brown-Conrady distortion (lens.h; schema aar-rig/2), each with its
// pose tanker_from_camera, and an optional image sensor (sensor.h; aar-rig/3).

#include <Eigen/Geometry>
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <optional>

#include "aar/lens.h"
#include "aar/sensor.h"
#include "aar/thermal.h"

namespace aar {

/// Rig file schemas: 1 = pinhole cameras, 2 = with "distortion" per camera,
/// 3 = also with a "sensor" block, 4 = also with an "lwir" block (a thermal
/// pair; older readers so refuse it rather than render it as visible).
/// Rigs are written as 2 only when a camera has distortion, as 3 only when
/// the rig has a sensor and as 4 only with lwir, so earlier rigs (and the
/// datasets made with them) are unchanged; all four are read.
inline constexpr const char* kRigSchemaV1 = "aar-rig/1";
inline constexpr const char* kRigSchemaV2 = "aar-rig/2";
inline constexpr const char* kRigSchemaV3 = "aar-rig/3";
inline constexpr const char* kRigSchemaV4 = "aar-rig/4";

struct Intrinsics {
  int width_px = 1024;      ///< image width [px]
  int height_px = 768;      ///< image height [px]
  double fx_px = 900.0;     ///< focal length along x [px]
  double fy_px = 900.0;     ///< focal length along y [px]
  double cx_px = 511.5;     ///< principal point x [px], OpenCV convention (pixel centres at integers)
  double cy_px = 383.5;     ///< principal point y [px]
  BrownConrady distortion;  ///< lens distortion (all zero: the ideal pinhole)

  Eigen::Matrix3d CameraMatrix() const;
  /// Pixel of a point in the camera frame (x right, y down, z forward), with
  /// the lens distortion; nullopt behind the camera or beyond the radius where
  /// the distortion model folds back (lens.h, RadiallyMonotonic).
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
  /// The image sensor of both cameras; none (the default): the ideal
  /// noise-free sensor, images exactly the rendered radiance.
  std::optional<SensorParams> sensor;
  /// A long-wave infrared pair instead (thermal.h; aar-rig/3): the renderer
  /// makes radiometric thermal images; exclusive with `sensor`.
  std::optional<ThermalCamera> lwir;

  /// right_from_left: OpenCV stereoCalibrate's (R, T).
  Eigen::Isometry3d RightFromLeft() const;
  /// Distance between the camera centres [m].
  double Baseline() const;
};

/// Reads a rig file; throws aar::Error naming the file and the bad field.
StereoRig LoadRig(const std::filesystem::path& path);

/// Whether any camera has lens distortion (the rig is then written as aar-rig/2).
bool HasDistortion(const StereoRig& rig);

/// JSON form used in rig files and frame sidecars: "fx_px" .. "cy_px", plus
/// "distortion" {k1, k2, p1, p2, k3} when the lens has any. RigToJson adds
/// "sensor" when the rig has one.
nlohmann::json IntrinsicsToJson(const Intrinsics& intrinsics);
nlohmann::json IsometryToJson(const Eigen::Isometry3d& a_from_b);
nlohmann::json RigToJson(const StereoRig& rig);
/// Parse helpers; `where` prefixes error messages. `allow_distortion`: the
/// schema is aar-rig/2 or 3 (a "distortion" object in aar-rig/1 is refused); the
/// distortion must be one-to-one inside the image (CheckDistortionInImage).
Intrinsics IntrinsicsFromJson(const nlohmann::json& j, int width, int height, const std::string& where,
                              bool allow_distortion = false);
Eigen::Isometry3d IsometryFromJson(const nlohmann::json& j, const std::string& where);
StereoRig RigFromJson(const nlohmann::json& j, const std::string& where);

}  // namespace aar
