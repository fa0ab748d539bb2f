#pragma once
// A z-buffer of a triangle mesh seen by a pinhole camera: the shelled
// model's visibility test and the window-bias prediction rasterize the
// receiver's mesh with it.

#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "aar/analyzer/mesh.h"
#include "aar/rig.h"

namespace aar {

struct DepthBuffer {
  int width = 0;
  int height = 0;
  std::vector<float> depth_m;  ///< row-major, +inf where no surface [m]
  float At(int x, int y) const { return depth_m[static_cast<size_t>(y) * static_cast<size_t>(width) + x]; }
};

/// Rasterizes `mesh` into a width_px x height_px z-buffer of the pinhole
/// camera `k` (its distortion ignored; pixel centres at integer
/// coordinates): depth along the optical axis, interpolated
/// perspective-correctly (1/z affine in the image), triangles clipped at
/// `near_m`, the nearest surface kept where triangles overlap.
DepthBuffer RasterizeDepth(const TriangleMesh& mesh, const Intrinsics& k, const Eigen::Isometry3d& cam_from_receiver,
                           double near_m);

}  // namespace aar
