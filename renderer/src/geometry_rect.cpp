#include "aar/renderer/geometry_rect.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace aar {
namespace {

// Clip-space half spaces, dot(plane, clip) >= 0: the frustum's four sides
// grown by the margin, and Vulkan's 0 <= z <= w (with the renderer's
// projection z is the near distance, so z <= w is the near plane; a relative
// 1e-9 keeps a vertex on it inside).
using Planes = std::array<Eigen::Vector4d, 6>;

Planes GrownFrustum(int width, int height, int margin_px) {
  const double gx = 1.0 + 2.0 * margin_px / width, gy = 1.0 + 2.0 * margin_px / height;
  return {Eigen::Vector4d(1, 0, 0, gx),  Eigen::Vector4d(-1, 0, 0, gx), Eigen::Vector4d(0, 1, 0, gy),
          Eigen::Vector4d(0, -1, 0, gy), Eigen::Vector4d(0, 0, 1, 0),   Eigen::Vector4d(0, 0, -1, 1.0 + 1e-9)};
}

// Bit i set: outside plane i.
unsigned Outcode(const Planes& planes, const Eigen::Vector4d& clip) {
  unsigned code = 0;
  for (size_t i = 0; i < planes.size(); ++i) code |= planes[i].dot(clip) < 0.0 ? 1u << i : 0u;
  return code;
}

// Bounds of projected framebuffer coordinates, grown by each point added.
struct Bounds {
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  void Add(const Eigen::Vector4d& clip, int width, int height) {
    if (clip.w() <= 0.0) return;  // only on the planes' common edge, where nothing is visible
    const double x = (clip.x() / clip.w() + 1.0) * width / 2.0;
    const double y = (clip.y() / clip.w() + 1.0) * height / 2.0;
    x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  }
};

// Sutherland-Hodgman: the part of a triangle inside the planes named by `codes`.
void AddClippedTriangle(const Planes& planes, unsigned codes, const std::array<Eigen::Vector4d, 3>& triangle, int width,
                        int height, Bounds& bounds) {
  std::vector<Eigen::Vector4d> poly(triangle.begin(), triangle.end()), next;
  for (size_t p = 0; p < planes.size() && !poly.empty(); ++p) {
    if (!(codes & (1u << p))) continue;
    next.clear();
    for (size_t i = 0; i < poly.size(); ++i) {
      const Eigen::Vector4d& a = poly[i];
      const Eigen::Vector4d& b = poly[(i + 1) % poly.size()];
      const double da = planes[p].dot(a), db = planes[p].dot(b);
      if (da >= 0.0) next.push_back(a);
      if ((da >= 0.0) != (db >= 0.0)) next.push_back(a + (b - a) * (da / (da - db)));
    }
    poly.swap(next);
  }
  for (const Eigen::Vector4d& v : poly) bounds.Add(v, width, height);
}

PixelRect ToPixels(const Bounds& b, int width, int height, int margin_px) {
  if (!(b.x0 <= b.x1 && b.y0 <= b.y1)) return PixelRect{};
  PixelRect r;
  r.x0 = static_cast<int>(std::clamp(std::floor(b.x0) - margin_px, 0.0, static_cast<double>(width)));
  r.y0 = static_cast<int>(std::clamp(std::floor(b.y0) - margin_px, 0.0, static_cast<double>(height)));
  r.x1 = static_cast<int>(std::clamp(std::ceil(b.x1) + margin_px, 0.0, static_cast<double>(width)));
  r.y1 = static_cast<int>(std::clamp(std::ceil(b.y1) + margin_px, 0.0, static_cast<double>(height)));
  return r;
}

}  // namespace

MeshGeometry MeshGeometryOf(const SceneModel& model) {
  MeshGeometry mesh;
  for (const Primitive& p : model.primitives) {
    const auto first = static_cast<uint32_t>(mesh.positions.size());
    for (const Vertex& v : p.vertices) {
      mesh.positions.emplace_back(v.position[0], v.position[1], v.position[2]);
      mesh.bounds.extend(mesh.positions.back());
    }
    for (uint32_t i : p.indices) mesh.indices.push_back(first + i);
  }
  return mesh;
}

PixelRect GeometryRect(const Eigen::Matrix4d& clip_from_object, const MeshGeometry& mesh, int width, int height,
                       int margin_px) {
  if (mesh.bounds.isEmpty()) return PixelRect{};
  // The box's corners, when all lie in front of the camera: the box's image
  // is inside their projections' bounds.
  Bounds box;
  bool box_in_front = true;
  for (int i = 0; i < 8 && box_in_front; ++i) {
    const Eigen::Vector4d clip =
        clip_from_object * mesh.bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)).homogeneous();
    box_in_front = clip.w() > 1e-6;
    box.Add(clip, width, height);
  }
  if (box_in_front) return ToPixels(box, width, height, margin_px);

  // The triangles, clipped where they cross a side of the grown frustum.
  const Planes planes = GrownFrustum(width, height, margin_px);
  std::vector<Eigen::Vector4d> clip(mesh.positions.size());
  std::vector<unsigned> codes(mesh.positions.size());
  for (size_t i = 0; i < clip.size(); ++i) {
    clip[i] = clip_from_object * mesh.positions[i].homogeneous();
    codes[i] = Outcode(planes, clip[i]);
  }
  Bounds bounds;
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    if (codes[a] & codes[b] & codes[c]) continue;  // wholly outside one plane
    const unsigned crossed = codes[a] | codes[b] | codes[c];
    if (crossed == 0) {
      for (uint32_t v : {a, b, c}) bounds.Add(clip[v], width, height);
    } else {
      AddClippedTriangle(planes, crossed, {clip[a], clip[b], clip[c]}, width, height, bounds);
    }
  }
  return ToPixels(bounds, width, height, margin_px);
}

}  // namespace aar
