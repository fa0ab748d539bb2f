#pragma once
// Reference point clouds of the receiver for ICP (thesis section 3.2).
//
// The thesis's full model is an evenly distributed point set over the C-12's
// exterior (48,686 points); its shelled model keeps only the points the
// tanker's stereo cameras see when the receiver approaches the refuelling
// envelope (7,772 points). Here the full model is an area-uniform random
// sample of the receiver mesh with a fixed seed, and the shelled model is the
// subset of the full model that passes a z-buffer visibility test against the
// mesh in either camera of the rig, with the receiver at the contact pose.
//
// Both models stay in the receiver frame, whatever their centroid: ICP
// estimates tanker_from_receiver directly, so every pose is reported for the
// receiver reference point (the model origin), which is the thesis's "center
// point transformation" of section 3.6 done once and for all.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "aar/analyzer/mesh.h"
#include "aar/pose.h"
#include "aar/rig.h"

namespace aar {

struct ReferenceModelOptions {
  size_t num_points = 48686;  ///< full-model points (thesis 3.2)
  uint64_t seed = 1;          ///< seed of the surface sampler (std::mt19937_64)
  /// Receiver pose used to shell the model; nullopt = the rig's
  /// contact_position_m with zero roll, pitch and yaw.
  std::optional<Pose> tanker_from_receiver;
  double depth_tolerance_m = 0.05;  ///< a point is visible up to this far behind the z-buffer [m]
  /// Half size of the pixel window of the visibility test: 1 = 3x3 (see ShellModel).
  int neighbourhood_radius_px = 1;
  int raster_width_px = 0;   ///< z-buffer width [px]; 0 = the camera's image width
  int raster_height_px = 0;  ///< z-buffer height [px]; 0 = the camera's image height
  /// false (default): keep points seen by at least one camera; true: by both.
  bool require_both_cameras = false;

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

struct ReferenceModel {
  std::string name;                                 ///< "full" or "shelled"
  std::vector<Eigen::Vector3d> points_in_receiver;  ///< receiver frame [m]
};

/// `num_points` points distributed uniformly by area over the mesh surface,
/// deterministic for a given seed on every platform: a triangle is drawn from
/// the cumulative area table, then a point inside it with the square-root
/// barycentric mapping (u = 1 - sqrt(r1), v = sqrt(r1) (1 - r2), w = sqrt(r1) r2).
/// Random reals come from the raw 64-bit output of std::mt19937_64 (53 bits
/// scaled into [0, 1)), never from std::uniform_real_distribution, whose
/// output is implementation-defined. Throws aar::Error on a mesh of zero area.
std::vector<Eigen::Vector3d> SampleSurface(const TriangleMesh& mesh, size_t num_points, uint64_t seed);

/// The full model: SampleSurface(mesh, options.num_points, options.seed).
ReferenceModel FullModel(const TriangleMesh& mesh, const ReferenceModelOptions& options = {});

/// The pose ShellModel uses: options.tanker_from_receiver or the contact pose.
Eigen::Isometry3d ShellTankerFromReceiver(const StereoRig& rig, const ReferenceModelOptions& options);

/// Visibility of receiver-frame points in one camera, tested against the mesh.
/// The mesh is rasterized into a z-buffer (pinhole model of `intrinsics`, pixel
/// centres at integer coordinates, depth along the optical axis interpolated
/// perspective-correctly, i.e. 1/z linear in the image, triangles clipped at
/// `near_m`). A point is visible when it lies in front of the near plane,
/// projects inside the image, and is no more than depth_tolerance_m behind the
/// z-buffer at SOME pixel of the (2r+1)^2 window around its nearest pixel. The
/// window makes the test slightly dilated: a surface point at a grazing angle,
/// whose own pixel centre samples a nearer part of the same surface, is still
/// kept; hidden surfaces further than r pixels from a silhouette are dropped.
std::vector<bool> VisibleInCamera(const std::vector<Eigen::Vector3d>& points_in_receiver, const TriangleMesh& mesh,
                                  const Intrinsics& intrinsics, const Eigen::Isometry3d& cam_from_receiver,
                                  double near_m, const ReferenceModelOptions& options = {});

/// The shelled model: the points of `full_points` visible in the left OR the
/// right camera (require_both_cameras = false) with the receiver at
/// ShellTankerFromReceiver(rig, options); cam_from_receiver =
/// inverse(tanker_from_cam) * tanker_from_receiver. Either camera, because a
/// surface seen by one camera is one the stereo pipeline can reconstruct at
/// some point of the approach, and the union is closer to the thesis's
/// "perspective the tanker's stereo cameras would see". Points keep their
/// order in `full_points`.
ReferenceModel ShellModel(const std::vector<Eigen::Vector3d>& full_points, const TriangleMesh& mesh,
                          const StereoRig& rig, const ReferenceModelOptions& options = {});

/// Writes points as a binary_little_endian PLY (element vertex, float x y z),
/// readable by Open3D, PCL and CloudCompare; atomic (aar::WriteFileAtomic).
/// `comments` become "comment" header lines (no newlines allowed).
void WritePly(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& points,
              const std::vector<std::string>& comments = {});

/// Reads the x, y, z properties of the vertex element of a PLY file: ascii,
/// binary_little_endian or binary_big_endian, scalar properties of any PLY
/// type, other properties skipped, elements after `vertex` ignored. Throws
/// aar::Error naming the file and the reason otherwise.
std::vector<Eigen::Vector3d> ReadPly(const std::filesystem::path& path);

}  // namespace aar
