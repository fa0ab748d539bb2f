#include "aar/rig.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "aar/error.h"
#include "aar/json_file.h"
#include "aar/json_number.h"

namespace aar {
namespace {

double FiniteNumber(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.contains(key) || !j.at(key).is_number()) throw Error(where + ": missing number '" + key + "'");
  const double v = j.at(key).get<double>();
  if (!std::isfinite(v)) throw Error(where + ": '" + key + "' is not finite");
  return v;
}

}  // namespace

Eigen::Matrix3d Intrinsics::CameraMatrix() const {
  Eigen::Matrix3d k;
  k << fx_px, 0, cx_px, 0, fy_px, cy_px, 0, 0, 1;
  return k;
}

std::optional<Eigen::Vector2d> Intrinsics::Project(const Eigen::Vector3d& point_in_cam) const {
  if (point_in_cam.z() <= 1e-9) return std::nullopt;
  if (distortion.IsZero()) {
    return Eigen::Vector2d(fx_px * point_in_cam.x() / point_in_cam.z() + cx_px,
                           fy_px * point_in_cam.y() / point_in_cam.z() + cy_px);
  }
  const Eigen::Vector2d x(point_in_cam.x() / point_in_cam.z(), point_in_cam.y() / point_in_cam.z());
  if (!RadiallyMonotonic(distortion, x.squaredNorm())) return std::nullopt;
  const Eigen::Vector2d d = Distort(distortion, x);
  return Eigen::Vector2d(fx_px * d.x() + cx_px, fy_px * d.y() + cy_px);
}

bool Intrinsics::Contains(const Eigen::Vector2d& pixel) const {
  return pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() < width_px - 0.5 && pixel.y() < height_px - 0.5;
}

Eigen::Isometry3d StereoRig::RightFromLeft() const {
  return right.tanker_from_camera.inverse() * left.tanker_from_camera;
}

double StereoRig::Baseline() const {
  return (right.tanker_from_camera.translation() - left.tanker_from_camera.translation()).norm();
}

bool HasDistortion(const StereoRig& rig) {
  return !rig.left.intrinsics.distortion.IsZero() || !rig.right.intrinsics.distortion.IsZero();
}

nlohmann::json IntrinsicsToJson(const Intrinsics& k) {
  nlohmann::json j = {{"fx_px", k.fx_px}, {"fy_px", k.fy_px}, {"cx_px", k.cx_px}, {"cy_px", k.cy_px}};
  const BrownConrady& d = k.distortion;
  if (!d.IsZero()) j["distortion"] = {{"k1", d.k1}, {"k2", d.k2}, {"p1", d.p1}, {"p2", d.p2}, {"k3", d.k3}};
  return j;
}

nlohmann::json IsometryToJson(const Eigen::Isometry3d& a_from_b) {
  const Eigen::Matrix3d r = a_from_b.linear();
  const Eigen::Vector3d t = a_from_b.translation();
  return {{"translation_m", {t.x(), t.y(), t.z()}},
          {"rotation", {{r(0, 0), r(0, 1), r(0, 2)}, {r(1, 0), r(1, 1), r(1, 2)}, {r(2, 0), r(2, 1), r(2, 2)}}}};
}

Intrinsics IntrinsicsFromJson(const nlohmann::json& j, int width, int height, const std::string& where,
                              bool allow_distortion) {
  Intrinsics k;
  k.width_px = width;
  k.height_px = height;
  k.fx_px = FiniteNumber(j, "fx_px", where);
  k.fy_px = FiniteNumber(j, "fy_px", where);
  k.cx_px = FiniteNumber(j, "cx_px", where);
  k.cy_px = FiniteNumber(j, "cy_px", where);
  if (k.fx_px <= 0 || k.fy_px <= 0) throw Error(where + ": focal lengths must be positive");
  if (j.contains("distortion")) {
    if (!allow_distortion) throw Error(where + ": 'distortion' needs schema \"" + std::string(kRigSchemaV2) + "\"");
    const nlohmann::json& d = j.at("distortion");
    const std::string at = where + ": distortion";
    if (!d.is_object()) throw Error(at + " must be an object {k1, k2, p1, p2, k3}");
    for (const auto& item : d.items()) {
      if (item.key() != "k1" && item.key() != "k2" && item.key() != "p1" && item.key() != "p2" && item.key() != "k3") {
        throw Error(at + "." + item.key() + " is not a Brown-Conrady coefficient (k1, k2, p1, p2, k3)");
      }
    }
    k.distortion = {FiniteNumber(d, "k1", at), FiniteNumber(d, "k2", at), FiniteNumber(d, "p1", at),
                    FiniteNumber(d, "p2", at), FiniteNumber(d, "k3", at)};
    CheckDistortionInImage(k.distortion, k.fx_px, k.fy_px, k.cx_px, k.cy_px, width, height, where);
  }
  return k;
}

Eigen::Isometry3d IsometryFromJson(const nlohmann::json& j, const std::string& where) {
  const auto& t = j.at("translation_m");
  const auto& r = j.at("rotation");
  if (!t.is_array() || t.size() != 3 || !r.is_array() || r.size() != 3) {
    throw Error(where + ": expected translation_m[3] and rotation[3][3]");
  }
  Eigen::Isometry3d a_from_b = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    a_from_b.translation()(i) = t.at(i).get<double>();
    if (!r.at(i).is_array() || r.at(i).size() != 3) throw Error(where + ": rotation must be 3x3");
    for (int c = 0; c < 3; ++c) a_from_b.linear()(i, c) = r.at(i).at(c).get<double>();
  }
  if (!a_from_b.matrix().allFinite()) throw Error(where + ": translation_m or rotation is not finite");
  const Eigen::Matrix3d rr = a_from_b.linear();
  if ((rr.transpose() * rr - Eigen::Matrix3d::Identity()).norm() > 1e-6 || rr.determinant() < 0.999) {
    throw Error(where + ": rotation is not a proper rotation matrix");
  }
  return a_from_b;
}

nlohmann::json RigToJson(const StereoRig& rig) {
  auto camera = [](const Camera& c) {
    nlohmann::json j = IntrinsicsToJson(c.intrinsics);
    j["tanker_from_camera"] = IsometryToJson(c.tanker_from_camera);
    return j;
  };
  const Eigen::Vector3d& contact = rig.contact_position_m;
  const char* schema = rig.lwir             ? kRigSchemaV4
                       : rig.sensor         ? kRigSchemaV3
                       : HasDistortion(rig) ? kRigSchemaV2
                                            : kRigSchemaV1;
  nlohmann::json j = {{"schema", schema},
                      {"image_width", rig.left.intrinsics.width_px},
                      {"image_height", rig.left.intrinsics.height_px},
                      {"cameras", {{"left", camera(rig.left)}, {"right", camera(rig.right)}}},
                      {"near_m", rig.near_m},
                      {"contact_position_m", {contact.x(), contact.y(), contact.z()}}};
  if (rig.sensor) j["sensor"] = SensorToJson(*rig.sensor);
  if (rig.lwir) j["lwir"] = ThermalToJson(*rig.lwir);
  return j;
}

StereoRig RigFromJson(const nlohmann::json& j, const std::string& where) {
  try {
    StereoRig rig;
    bool allow_distortion = false;
    bool allow_sensor = false;
    bool allow_lwir = false;
    if (j.contains("schema")) {
      const nlohmann::json& schema = j.at("schema");
      if (!schema.is_string() ||
          (schema != kRigSchemaV1 && schema != kRigSchemaV2 && schema != kRigSchemaV3 && schema != kRigSchemaV4)) {
        throw Error(where + ": unknown schema " + schema.dump() + " (expected \"" + kRigSchemaV1 + "\", \"" +
                    kRigSchemaV2 + "\", \"" + kRigSchemaV3 + "\" or \"" + kRigSchemaV4 + "\")");
      }
      allow_lwir = schema == kRigSchemaV4;
      allow_distortion = schema != kRigSchemaV1;
      allow_sensor = schema == kRigSchemaV3 || schema == kRigSchemaV4;
    }
    const int width = static_cast<int>(JsonInteger(j.at("image_width"), 1, 16384, where + ": image_width"));
    const int height = static_cast<int>(JsonInteger(j.at("image_height"), 1, 16384, where + ": image_height"));
    auto camera = [&](const char* name) {
      const nlohmann::json& c = j.at("cameras").at(name);
      Camera cam;
      cam.intrinsics = IntrinsicsFromJson(c, width, height, where + ": camera " + name, allow_distortion);
      cam.tanker_from_camera = IsometryFromJson(c.at("tanker_from_camera"), where + ": camera " + name);
      return cam;
    };
    rig.left = camera("left");
    rig.right = camera("right");
    if (j.contains("near_m")) rig.near_m = FiniteNumber(j, "near_m", where);
    if (!(rig.near_m > 0.0)) throw Error(where + ": near_m must be positive (the near clip plane) [m]");
    if (j.contains("contact_position_m")) {
      const nlohmann::json& contact = j.at("contact_position_m");
      if (!contact.is_array() || contact.size() != 3) throw Error(where + ": contact_position_m must be [x, y, z]");
      for (int i = 0; i < 3; ++i) rig.contact_position_m(i) = contact.at(i).get<double>();
      if (!rig.contact_position_m.allFinite()) throw Error(where + ": contact_position_m is not finite");
    }
    if (j.contains("sensor")) {
      if (!allow_sensor) throw Error(where + ": 'sensor' needs schema \"" + std::string(kRigSchemaV3) + "\"");
      rig.sensor = SensorFromJson(j.at("sensor"), where);
    }
    if (j.contains("lwir")) {
      if (!allow_lwir) throw Error(where + ": 'lwir' needs schema \"" + std::string(kRigSchemaV4) + "\"");
      if (rig.sensor) throw Error(where + ": 'sensor' and 'lwir': a rig's cameras are visible or thermal, not both");
      rig.lwir = ThermalFromJson(j.at("lwir"), where);
    }
    return rig;
  } catch (const nlohmann::json::exception& e) {
    throw Error(where + ": " + e.what());
  }
}

StereoRig LoadRig(const std::filesystem::path& path) { return RigFromJson(ReadJsonFile(path), path.string()); }

}  // namespace aar
