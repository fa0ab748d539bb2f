#pragma once
// The image rectangle that can hold a model's geometry (pure maths, no
// Vulkan): only this rectangle is rendered with MSAA, the rest of the frame is
// background (docs/rendering.md). The model's bounding box gives it when the
// box lies in front of the camera; a box that reaches behind the camera (the
// tanker's, which contains the cameras) would give the whole image, so then
// the model's triangles are clipped against the view frustum, grown by the
// margin, and its near plane, and the rectangle covers what is left of them.

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "aar/renderer/scene_model.h"

namespace aar {

/// A pixel rectangle [x0, x1) x [y0, y1).
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};

/// A model's triangles (object frame) and their bounding box.
struct MeshGeometry {
  Eigen::AlignedBox3d bounds;
  std::vector<Eigen::Vector3d> positions;  ///< [m]
  std::vector<uint32_t> indices;           ///< three per triangle, into positions
};

/// Every primitive's triangles of `model` in one list.
MeshGeometry MeshGeometryOf(const SceneModel& model);

/// Conservative framebuffer rectangle covering every part of `mesh` that
/// clip_from_object (a Vulkan clip matrix: visible where |x|, |y| <= w and
/// 0 <= z <= w) can put inside the image, grown by `margin_px` on every side
/// and clamped to the image; empty when no part of the mesh comes within
/// `margin_px` of the image. From the bounding box's corners when all lie in
/// front of the camera (w > 0), else from the triangles clipped against the
/// frustum grown by `margin_px` (Sutherland-Hodgman in clip space).
PixelRect GeometryRect(const Eigen::Matrix4d& clip_from_object, const MeshGeometry& mesh, int width, int height,
                       int margin_px);

}  // namespace aar
