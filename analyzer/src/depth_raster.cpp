#include "aar/analyzer/depth_raster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace aar {
namespace {

// Sutherland-Hodgman clip of a triangle against the half space z >= near.
int ClipNear(const std::array<Eigen::Vector3d, 3>& in, double near_m, std::array<Eigen::Vector3d, 4>& out) {
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d& a = in[static_cast<size_t>(i)];
    const Eigen::Vector3d& b = in[static_cast<size_t>((i + 1) % 3)];
    const bool a_in = a.z() >= near_m;
    const bool b_in = b.z() >= near_m;
    if (a_in) out[static_cast<size_t>(n++)] = a;
    if (a_in != b_in) out[static_cast<size_t>(n++)] = a + (b - a) * ((near_m - a.z()) / (b.z() - a.z()));
  }
  return n;
}

// Scan-converts one triangle (camera frame, all z >= near) into the buffer.
void RasterizeTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                       const Intrinsics& k, DepthBuffer& buffer) {
  const std::array<Eigen::Vector3d, 3> cam = {a, b, c};
  std::array<Eigen::Vector2d, 3> px;
  std::array<double, 3> inverse_z;
  for (size_t i = 0; i < 3; ++i) {
    inverse_z[i] = 1.0 / cam[i].z();
    px[i] =
        Eigen::Vector2d(k.fx_px * cam[i].x() * inverse_z[i] + k.cx_px, k.fy_px * cam[i].y() * inverse_z[i] + k.cy_px);
  }
  const auto edge = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, double x, double y) {
    return (q.x() - p.x()) * (y - p.y()) - (q.y() - p.y()) * (x - p.x());
  };
  const double area = edge(px[0], px[1], px[2].x(), px[2].y());
  if (!(std::abs(area) > 1e-12)) return;  // degenerate or edge-on
  const double min_u = std::min({px[0].x(), px[1].x(), px[2].x()});
  const double max_u = std::max({px[0].x(), px[1].x(), px[2].x()});
  const double min_v = std::min({px[0].y(), px[1].y(), px[2].y()});
  const double max_v = std::max({px[0].y(), px[1].y(), px[2].y()});
  const int x0 = static_cast<int>(std::max(0.0, std::ceil(min_u)));
  const int x1 = static_cast<int>(std::min(buffer.width - 1.0, std::floor(max_u)));
  const int y0 = static_cast<int>(std::max(0.0, std::ceil(min_v)));
  const int y1 = static_cast<int>(std::min(buffer.height - 1.0, std::floor(max_v)));
  const double inverse_area = 1.0 / area;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      // Barycentric weights of the pixel centre; closed edges (>= 0) so that
      // shared edges have no cracks (a pixel written twice keeps the minimum).
      const double w0 = edge(px[1], px[2], x, y) * inverse_area;
      const double w1 = edge(px[2], px[0], x, y) * inverse_area;
      const double w2 = edge(px[0], px[1], x, y) * inverse_area;
      if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
      // Perspective-correct depth: 1/z is affine in image coordinates.
      const double z = 1.0 / (w0 * inverse_z[0] + w1 * inverse_z[1] + w2 * inverse_z[2]);
      float& stored = buffer.depth_m[static_cast<size_t>(y) * static_cast<size_t>(buffer.width) + x];
      stored = std::min(stored, static_cast<float>(z));
    }
  }
}

}  // namespace

DepthBuffer RasterizeDepth(const TriangleMesh& mesh, const Intrinsics& k, const Eigen::Isometry3d& cam_from_receiver,
                           double near_m) {
  DepthBuffer buffer;
  buffer.width = k.width_px;
  buffer.height = k.height_px;
  buffer.depth_m.assign(static_cast<size_t>(k.width_px) * static_cast<size_t>(k.height_px),
                        std::numeric_limits<float>::infinity());
  std::vector<Eigen::Vector3d> vertices_in_cam(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) vertices_in_cam[i] = cam_from_receiver * mesh.vertices[i];
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const std::array<Eigen::Vector3d, 3> tri = {vertices_in_cam[static_cast<size_t>(t[0])],
                                                vertices_in_cam[static_cast<size_t>(t[1])],
                                                vertices_in_cam[static_cast<size_t>(t[2])]};
    if (tri[0].z() >= near_m && tri[1].z() >= near_m && tri[2].z() >= near_m) {
      RasterizeTriangle(tri[0], tri[1], tri[2], k, buffer);
      continue;
    }
    std::array<Eigen::Vector3d, 4> clipped;
    const int n = ClipNear(tri, near_m, clipped);
    for (int i = 1; i + 1 < n; ++i) {
      RasterizeTriangle(clipped[0], clipped[static_cast<size_t>(i)], clipped[static_cast<size_t>(i + 1)], k, buffer);
    }
  }
  return buffer;
}

}  // namespace aar
