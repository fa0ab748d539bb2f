#include "aar/analyzer/export_bop.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "aar/analyzer/bop_metrics.h"
#include "aar/analyzer/stereo_truth.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/text.h"

namespace aar {
namespace {

constexpr const char* kScene = "000001";
constexpr int kObjectId = 1;

nlohmann::json RowMajor(const Eigen::Matrix3d& r) {
  nlohmann::json j = nlohmann::json::array();
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) j.push_back(r(i, k));
  return j;
}

nlohmann::json Millimetres(const Eigen::Vector3d& t_m) {
  return {t_m.x() * 1000.0, t_m.y() * 1000.0, t_m.z() * 1000.0};
}

std::string EncodePngOrThrow(const cv::Mat& image, const std::string& what) {
  std::vector<uint8_t> bytes;
  if (!cv::imencode(".png", image, bytes, {cv::IMWRITE_PNG_COMPRESSION, 3}))
    throw Error(what + ": PNG encoding failed");
  return std::string(bytes.begin(), bytes.end());
}

// [x, y, width, height] of the non-zero pixels; BOP's [-1, -1, 0, 0] when none.
nlohmann::json BoundingBox(const cv::Mat& mask) {
  if (cv::countNonZero(mask) == 0) return {-1, -1, 0, 0};
  const cv::Rect box = cv::boundingRect(mask);
  return {box.x, box.y, box.width, box.height};
}

// Reads an 8-bit grey PNG of the dataset (already verified).
cv::Mat ReadGrey(const std::filesystem::path& path) {
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (image.empty() || image.type() != CV_8UC1) throw Error(path.string() + ": not an 8-bit grey PNG");
  return image;
}

nlohmann::json CameraJson(const Intrinsics& k) {
  return {{"cx", k.cx_px},
          {"cy", k.cy_px},
          {"fx", k.fx_px},
          {"fy", k.fy_px},
          {"width", k.width_px},
          {"height", k.height_px},
          {"depth_scale", kBopDepthScaleMm}};
}

nlohmann::json ModelInfo(const TriangleMesh& mesh) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Eigen::Vector3d size = hi - lo;
  return {{"diameter", BopObject(mesh).diameter_m() * 1000.0},
          {"min_x", lo.x() * 1000.0},
          {"min_y", lo.y() * 1000.0},
          {"min_z", lo.z() * 1000.0},
          {"size_x", size.x() * 1000.0},
          {"size_y", size.y() * 1000.0},
          {"size_z", size.z() * 1000.0}};
}

// One camera type: test_<side>/000001/.
void ExportCamera(const ExportSource& source, const std::string& side, const std::filesystem::path& out,
                  ExportResult& result) {
  const std::string dir = "test_" + side + "/" + kScene + "/";
  nlohmann::json scene_camera = nlohmann::json::object(), scene_gt = nlohmann::json::object();
  nlohmann::json scene_gt_info = nlohmann::json::object();
  for (const FrameSidecar& frame : source.frames) {
    const Camera& camera = side == "left" ? frame.rig.left : frame.rig.right;
    const std::string stem = FrameStem(frame.index);
    const std::string id = std::to_string(frame.index);
    WriteExportFile(out, dir + "rgb/" + stem + ".png", ReadVerifiedFile(source, frame.files.at(side)), result);

    const DepthTruth truth = ReadDepthTruth(source.dataset.folder() / frame.files.at(side + "_depth").path,
                                            source.dataset.folder() / frame.files.at(side + "_mask").path);
    cv::Mat depth(truth.depth_m.size(), CV_16UC1);
    for (int y = 0; y < depth.rows; ++y) {
      for (int x = 0; x < depth.cols; ++x) {
        const double counts = std::round(truth.depth_m.at<float>(y, x) * 1000.0 / kBopDepthScaleMm);
        depth.at<uint16_t>(y, x) = counts >= 1.0 && counts <= 65535.0 ? static_cast<uint16_t>(counts) : 0;
      }
    }
    WriteExportFile(out, dir + "depth/" + stem + ".png", EncodePngOrThrow(depth, dir + "depth/" + stem + ".png"),
                    result);
    const cv::Mat silhouette = ReadGrey(source.dataset.folder() / frame.files.at(side + "_silhouette").path) == 255;
    const cv::Mat visible = truth.ids == kReceiverId;
    const std::string mask_name = stem + "_000000.png";
    WriteExportFile(out, dir + "mask/" + mask_name, EncodePngOrThrow(silhouette, mask_name), result);
    WriteExportFile(out, dir + "mask_visib/" + mask_name, EncodePngOrThrow(visible, mask_name), result);

    const Eigen::Isometry3d cam_from_tanker = camera.tanker_from_camera.inverse();
    const Eigen::Isometry3d cam_from_receiver = cam_from_tanker * IsometryFromPose(frame.tanker_from_target);
    const Eigen::Matrix3d k = camera.intrinsics.CameraMatrix();
    scene_camera[id] = {{"cam_K", RowMajor(k)},
                        {"depth_scale", kBopDepthScaleMm},
                        {"cam_R_w2c", RowMajor(cam_from_tanker.linear())},
                        {"cam_t_w2c", Millimetres(cam_from_tanker.translation())}};
    scene_gt[id] = nlohmann::json::array({{{"obj_id", kObjectId},
                                           {"cam_R_m2c", RowMajor(cam_from_receiver.linear())},
                                           {"cam_t_m2c", Millimetres(cam_from_receiver.translation())}}});
    const int all = cv::countNonZero(silhouette);
    const int visib = cv::countNonZero(visible);
    const int valid = cv::countNonZero(silhouette & (depth > 0));
    scene_gt_info[id] = nlohmann::json::array({{{"bbox_obj", BoundingBox(silhouette)},
                                                {"bbox_visib", BoundingBox(visible)},
                                                {"px_count_all", all},
                                                {"px_count_valid", valid},
                                                {"px_count_visib", visib},
                                                {"visib_fract", all > 0 ? static_cast<double>(visib) / all : 0.0}}});
  }
  WriteExportFile(out, dir + "scene_camera.json", scene_camera.dump(2) + "\n", result);
  WriteExportFile(out, dir + "scene_gt.json", scene_gt.dump(2) + "\n", result);
  WriteExportFile(out, dir + "scene_gt_info.json", scene_gt_info.dump(2) + "\n", result);
}

}  // namespace

std::string BopModelPly(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3d> normals(mesh.vertices.size(), Eigen::Vector3d::Zero());
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[static_cast<size_t>(t[0])];
    const Eigen::Vector3d& b = mesh.vertices[static_cast<size_t>(t[1])];
    const Eigen::Vector3d& c = mesh.vertices[static_cast<size_t>(t[2])];
    const Eigen::Vector3d area_normal = (b - a).cross(c - a);  // length: twice the area; outward (counter-clockwise)
    for (int i = 0; i < 3; ++i) normals[static_cast<size_t>(t[i])] += area_normal;
  }
  std::string text =
      "ply\nformat ascii 1.0\ncomment aar-analyze export: receiver, receiver frame, mm\nelement vertex " +
      std::to_string(mesh.vertices.size()) +
      "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
      "property float nz\nelement face " +
      std::to_string(mesh.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d p = mesh.vertices[i] * 1000.0;
    const double norm = normals[i].norm();
    const Eigen::Vector3d n = norm > 0.0 ? Eigen::Vector3d(normals[i] / norm) : Eigen::Vector3d::Zero();
    text += FormatFixed(p.x(), 4) + " " + FormatFixed(p.y(), 4) + " " + FormatFixed(p.z(), 4) + " " +
            FormatFixed(n.x(), 6) + " " + FormatFixed(n.y(), 6) + " " + FormatFixed(n.z(), 6) + "\n";
  }
  for (const Eigen::Vector3i& t : mesh.triangles) {
    text += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  }
  return text;
}

ExportResult ExportBop(const ExportOptions& options) {
  const ExportSource source = ReadExportSource(options);
  if (HasDistortion(source.frames.front().rig)) {
    throw Error(options.dataset.string() +
                ": BOP's camera model is a pinhole (cam_K), and this dataset's cameras have lens distortion");
  }
  // Open has checked the copy against the manifest's SHA-256 where the manifest lists it.
  if (source.dataset.Input(kReceiverModelName) == nullptr ||
      !source.dataset.manifest().files.contains(kReceiverModelName)) {
    throw Error(source.dataset.PathOf(kReceiverModelName) + ": missing, or not listed in manifest.json");
  }
  const TriangleMesh mesh = LoadInputMesh(source.dataset, kReceiverModelName);
  // The right camera type needs right-camera truth in every frame; every file is checked before writing.
  bool right = true;
  for (const FrameSidecar& frame : source.frames) {
    for (const char* role : {"left", "right"}) ReadVerifiedFile(source, frame.files.at(role));
    for (const char* role : {"left_depth", "left_mask", "left_silhouette"}) {
      ReadVerifiedFile(source, RequireFile(source, frame, role, "--depth"));
    }
    for (const char* role : {"right_depth", "right_mask", "right_silhouette"}) {
      if (!frame.files.contains(role)) {
        right = false;
      } else {
        ReadVerifiedFile(source, frame.files.at(role));
      }
    }
  }
  ExportResult result;
  result.frames = source.frames.size();
  WriteExportFile(options.out, "models/obj_000001.ply", BopModelPly(mesh), result);
  WriteExportFile(options.out, "models/models_info.json", nlohmann::json{{"1", ModelInfo(mesh)}}.dump(2) + "\n",
                  result);
  const StereoRig& rig = source.frames.front().rig;
  WriteExportFile(options.out, "camera_left.json", CameraJson(rig.left.intrinsics).dump(2) + "\n", result);
  ExportCamera(source, "left", options.out, result);
  if (right) {
    WriteExportFile(options.out, "camera_right.json", CameraJson(rig.right.intrinsics).dump(2) + "\n", result);
    ExportCamera(source, "right", options.out, result);
  } else {
    result.notes.push_back("no test_right: the dataset has no right-camera depth truth (render with --depth-right)");
  }
  return result;
}

}  // namespace aar
