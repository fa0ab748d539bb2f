#pragma once
// Pinhole projection as a Vulkan clip-space matrix (pure maths, no Vulkan).

#include <Eigen/Geometry>

#include "aar/rig.h"

namespace aar {

/// clip_from_cam for an OpenCV camera frame (x right, y down, z forward):
/// reversed infinite depth (z_ndc = near / z, depth test GREATER, clear 0) and
/// w_clip = z_cam. The image is moved by (-jitter_x, -jitter_y) pixels so that
/// every sample position s inside a pixel looks at s + jitter (docs/rendering.md).
/// OpenCV pixel (u, v) lands on framebuffer coordinate (u + 0.5, v + 0.5).
Eigen::Matrix4d ClipFromCamera(const Intrinsics& intrinsics, double near_m, double jitter_x_px = 0.0,
                               double jitter_y_px = 0.0);

}  // namespace aar

#include <vector>

namespace aar {

/// Fraction of `points_in_object` (object frame) that project inside the
/// camera's image and lie in front of it, for the object at tanker_from_object.
double InViewFraction(const std::vector<Eigen::Vector3d>& points_in_object, const Camera& camera,
                      const Eigen::Isometry3d& tanker_from_object);

}  // namespace aar
