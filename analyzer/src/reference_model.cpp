#include "aar/analyzer/reference_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "aar/analyzer/depth_raster.h"
#include "aar/error.h"
#include "aar/file_io.h"

namespace aar {
namespace {

// A real in [0, 1) from the top 53 bits of one raw mt19937_64 draw; the raw
// sequence is fixed by the C++ standard, so samples match on every platform.
double Uniform01(std::mt19937_64& generator) { return static_cast<double>(generator() >> 11) * 0x1.0p-53; }

// Intrinsics of a raster of width x height covering the same field of view
// (pixel centres at integers, so the image edge -0.5 maps to -0.5). Pinhole:
// what a camera sees does not depend on its lens, only the image's extent
// does, and a lens's distortion leaves the receiver at contact in view.
Intrinsics ScaledIntrinsics(const Intrinsics& k, int width, int height) {
  Intrinsics s = k;
  s.distortion = BrownConrady{};
  const double sx = static_cast<double>(width) / k.width_px;
  const double sy = static_cast<double>(height) / k.height_px;
  s.width_px = width;
  s.height_px = height;
  s.fx_px = k.fx_px * sx;
  s.fy_px = k.fy_px * sy;
  s.cx_px = (k.cx_px + 0.5) * sx - 0.5;
  s.cy_px = (k.cy_px + 0.5) * sy - 0.5;
  return s;
}

}  // namespace

std::string ToString(ShellCameras cameras) {
  switch (cameras) {
    case ShellCameras::kLeft:
      return "left";
    case ShellCameras::kEither:
      return "either";
    case ShellCameras::kBoth:
      return "both";
  }
  return "both";
}

ShellCameras ParseShellCameras(const std::string& text) {
  if (text == "left") return ShellCameras::kLeft;
  if (text == "either") return ShellCameras::kEither;
  if (text == "both") return ShellCameras::kBoth;
  throw Error("shell cameras '" + text + "': expected left, either or both");
}

ReferenceModelOptions ReferenceModelOptions::Loose() {
  ReferenceModelOptions o;
  o.cameras = ShellCameras::kEither;
  o.depth_tolerance_m = 0.05;
  o.plane_depth_test = false;
  o.neighbourhood_radius_px = 1;
  o.raster_scale = 1;
  o.min_incidence_deg = -180.0;
  return o;
}

void ReferenceModelOptions::Check() const {
  if (num_points == 0 || num_points > kMaxReferencePoints) {
    throw Error("reference model: num_points (--points) " + std::to_string(num_points) + " must be 1 to " +
                std::to_string(kMaxReferencePoints));
  }
  if (!(depth_tolerance_m >= 0.0) || !std::isfinite(depth_tolerance_m)) {
    throw Error("reference model: depth_tolerance_m must be finite and >= 0");
  }
  if (neighbourhood_radius_px < 0 || neighbourhood_radius_px > 16) {
    throw Error("reference model: neighbourhood_radius_px must be in [0, 16]");
  }
  if (raster_scale < 1 || raster_scale > 8) throw Error("reference model: raster_scale must be in [1, 8]");
  if (raster_width_px < 0 || raster_height_px < 0 || raster_width_px > 16384 || raster_height_px > 16384) {
    throw Error("reference model: raster size must be in [0, 16384] (0 = raster_scale x image size)");
  }
  if (!(min_incidence_deg < 90.0)) throw Error("reference model: min_incidence_deg must be below 90");
}

ReferenceModel SampleSurfaceWithNormals(const TriangleMesh& mesh, size_t num_points, uint64_t seed) {
  std::vector<double> cumulative_area(mesh.triangles.size());
  double total = 0.0;
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    total += TriangleArea(mesh, i);
    cumulative_area[i] = total;
  }
  if (!(total > 0.0) || !std::isfinite(total)) throw Error("SampleSurface: the mesh has no surface area");

  std::mt19937_64 generator(seed);
  ReferenceModel sample;
  sample.points_in_receiver.reserve(num_points);
  sample.normals_in_receiver.reserve(num_points);
  for (size_t n = 0; n < num_points; ++n) {
    const double pick = Uniform01(generator) * total;
    const size_t i =
        std::min<size_t>(static_cast<size_t>(std::upper_bound(cumulative_area.begin(), cumulative_area.end(), pick) -
                                             cumulative_area.begin()),
                         cumulative_area.size() - 1);
    const double sqrt_r1 = std::sqrt(Uniform01(generator));
    const double r2 = Uniform01(generator);
    const Eigen::Vector3i& t = mesh.triangles[i];
    const Eigen::Vector3d& a = mesh.vertices[static_cast<size_t>(t[0])];
    const Eigen::Vector3d& b = mesh.vertices[static_cast<size_t>(t[1])];
    const Eigen::Vector3d& c = mesh.vertices[static_cast<size_t>(t[2])];
    sample.points_in_receiver.push_back((1.0 - sqrt_r1) * a + sqrt_r1 * (1.0 - r2) * b + sqrt_r1 * r2 * c);
    // A triangle drawn has positive area, so its normal is defined.
    sample.normals_in_receiver.push_back((b - a).cross(c - a).normalized());
  }
  return sample;
}

std::vector<Eigen::Vector3d> SampleSurface(const TriangleMesh& mesh, size_t num_points, uint64_t seed) {
  return SampleSurfaceWithNormals(mesh, num_points, seed).points_in_receiver;
}

ReferenceModel FullModel(const TriangleMesh& mesh, const ReferenceModelOptions& options) {
  options.Check();
  ReferenceModel full = SampleSurfaceWithNormals(mesh, options.num_points, options.seed);
  full.name = "full";
  return full;
}

Eigen::Isometry3d ShellTankerFromReceiver(const StereoRig& rig, const ReferenceModelOptions& options) {
  if (options.tanker_from_receiver) return IsometryFromPose(*options.tanker_from_receiver);
  Eigen::Isometry3d tanker_from_receiver = Eigen::Isometry3d::Identity();
  tanker_from_receiver.translation() = rig.contact_position_m;
  return tanker_from_receiver;
}

std::vector<bool> VisibleInCamera(const std::vector<Eigen::Vector3d>& points_in_receiver,
                                  const std::vector<Eigen::Vector3d>& normals_in_receiver, const TriangleMesh& mesh,
                                  const Intrinsics& intrinsics, const Eigen::Isometry3d& cam_from_receiver,
                                  double near_m, const ReferenceModelOptions& options) {
  options.Check();
  const bool with_normals = !normals_in_receiver.empty();
  if (with_normals && normals_in_receiver.size() != points_in_receiver.size()) {
    throw Error("visibility test: " + std::to_string(normals_in_receiver.size()) + " normals for " +
                std::to_string(points_in_receiver.size()) + " points");
  }
  const Intrinsics k = ScaledIntrinsics(
      intrinsics, options.raster_width_px > 0 ? options.raster_width_px : options.raster_scale * intrinsics.width_px,
      options.raster_height_px > 0 ? options.raster_height_px : options.raster_scale * intrinsics.height_px);
  const DepthBuffer buffer = RasterizeDepth(mesh, k, cam_from_receiver, near_m);
  const int r = options.neighbourhood_radius_px;
  const bool plane_test = with_normals && options.plane_depth_test;
  const bool incidence_test = with_normals && options.min_incidence_deg >= -90.0;
  const double min_sine = std::sin(options.min_incidence_deg * M_PI / 180.0);
  std::vector<bool> visible(points_in_receiver.size(), false);
  for (size_t i = 0; i < points_in_receiver.size(); ++i) {
    const Eigen::Vector3d p = cam_from_receiver * points_in_receiver[i];
    if (p.z() < near_m) continue;
    const auto pixel = k.Project(p);
    if (!pixel || !k.Contains(*pixel)) continue;
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    if (with_normals) {
      n = cam_from_receiver.linear() * normals_in_receiver[i];
      // sin(angle between the ray and the surface) = -n . ray (camera at the origin).
      if (incidence_test && !(-n.dot(p.normalized()) >= min_sine)) continue;
    }
    const int px = static_cast<int>(std::floor(pixel->x() + 0.5));
    const int py = static_cast<int>(std::floor(pixel->y() + 0.5));
    for (int y = std::max(0, py - r); y <= std::min(buffer.height - 1, py + r) && !visible[i]; ++y) {
      for (int x = std::max(0, px - r); x <= std::min(buffer.width - 1, px + r); ++x) {
        double z = p.z();
        if (plane_test) {
          // The ray through the pixel centre, (u, v, 1) scaled by depth, meets
          // the plane n . (X - p) = 0 at depth n . p / n . (u, v, 1).
          const Eigen::Vector3d ray((x - k.cx_px) / k.fx_px, (y - k.cy_px) / k.fy_px, 1.0);
          const double denominator = n.dot(ray);
          if (std::abs(denominator) > 1e-9) z = n.dot(p) / denominator;
        }
        if (z <= static_cast<double>(buffer.At(x, y)) + options.depth_tolerance_m) {
          visible[i] = true;
          break;
        }
      }
    }
  }
  return visible;
}

ReferenceModel ShellModel(const ReferenceModel& full, const TriangleMesh& mesh, const StereoRig& rig,
                          const ReferenceModelOptions& options) {
  const Eigen::Isometry3d tanker_from_receiver = ShellTankerFromReceiver(rig, options);
  const auto visible_in = [&](const Camera& camera) {
    return VisibleInCamera(full.points_in_receiver, full.normals_in_receiver, mesh, camera.intrinsics,
                           camera.tanker_from_camera.inverse() * tanker_from_receiver, rig.near_m, options);
  };
  const std::vector<bool> left = visible_in(rig.left);
  const std::vector<bool> right =
      options.cameras == ShellCameras::kLeft ? std::vector<bool>(left.size(), true) : visible_in(rig.right);
  const bool with_normals = !full.normals_in_receiver.empty();
  ReferenceModel shelled{"shelled", {}, {}};
  for (size_t i = 0; i < full.points_in_receiver.size(); ++i) {
    const bool keep = options.cameras == ShellCameras::kEither ? (left[i] || right[i]) : (left[i] && right[i]);
    if (!keep) continue;
    shelled.points_in_receiver.push_back(full.points_in_receiver[i]);
    if (with_normals) shelled.normals_in_receiver.push_back(full.normals_in_receiver[i]);
  }
  return shelled;
}

}  // namespace aar
