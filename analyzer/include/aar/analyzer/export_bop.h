#pragma once
// BOP (Hodan et al., the 6-DoF object pose benchmark), scenewise layout, the
// receiver as object 1 and each camera as a camera type:
//
//   OUT/camera_left.json, camera_right.json     cx, cy, fx, fy, width, height, depth_scale
//   OUT/models/obj_000001.ply                   receiver mesh, ascii, mm, vertex normals
//   OUT/models/models_info.json                 diameter, min_x/y/z, size_x/y/z [mm]
//   OUT/test_left/000001/rgb/IIIIII.png         the left image (IIIIII = frame index)
//   OUT/test_left/000001/depth/IIIIII.png       16-bit depth, Z [mm] = value * depth_scale, 0 = none
//   OUT/test_left/000001/mask/IIIIII_000000.png        the receiver's whole silhouette (255)
//   OUT/test_left/000001/mask_visib/IIIIII_000000.png  its visible part (255)
//   OUT/test_left/000001/scene_camera.json      cam_K, depth_scale, cam_R_w2c, cam_t_w2c (world = tanker frame)
//   OUT/test_left/000001/scene_gt.json          obj_id, cam_R_m2c, cam_t_m2c [mm]: cam_from_receiver
//   OUT/test_left/000001/scene_gt_info.json     bbox_obj, bbox_visib, px_count_all/valid/visib, visib_fract
//   OUT/test_right/000001/...                   the same for the right camera (datasets with --depth-right)
//
// Rotations row-major, translations in mm, OpenCV camera frame. The model
// frame is the receiver frame (origin at the reference point, x forward, y
// left, z up), so cam_from_receiver applies to the model as it is.

#include <Eigen/Core>
#include <vector>

#include "aar/analyzer/export_source.h"
#include "aar/analyzer/mesh.h"

namespace aar {

/// Depth image unit [mm per count]: 65535 counts cover 196.6 m (region A ends at 175 m).
inline constexpr double kBopDepthScaleMm = 3.0;

/// The receiver mesh as BOP's ascii PLY (mm; each vertex's normal the
/// area-weighted mean of its triangles' normals).
std::string BopModelPly(const TriangleMesh& mesh);

ExportResult ExportBop(const ExportOptions& options);

}  // namespace aar
