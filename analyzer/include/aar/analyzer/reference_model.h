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

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "aar/analyzer/mesh.h"
#include "aar/pose.h"
#include "aar/rig.h"

namespace aar {

/// Which cameras of the rig must see a point for the shell to keep it.
enum class ShellCameras {
  kLeft,    ///< the left camera (the disparity map's reference view)
  kEither,  ///< at least one camera (the first version's shell)
  kBoth,    ///< both cameras: a surface stereo can reconstruct (default)
};
/// "left" / "either" / "both"; the parser throws aar::Error on other text.
std::string ToString(ShellCameras cameras);
ShellCameras ParseShellCameras(const std::string& text);

/// Most full-model points Check() accepts (about 1 GB of points and normals).
inline constexpr size_t kMaxReferencePoints = 10'000'000;

struct ReferenceModelOptions {
  size_t num_points = 48686;  ///< full-model points (thesis 3.2), 1 to kMaxReferencePoints
  uint64_t seed = 1;          ///< seed of the surface sampler (std::mt19937_64)
  /// Receiver pose used to shell the model; nullopt = the rig's
  /// contact_position_m with zero roll, pitch and yaw.
  std::optional<Pose> tanker_from_receiver;
  ShellCameras cameras = ShellCameras::kBoth;  ///< cameras that must see a kept point
  /// A point is visible when its own surface plane, intersected with the ray
  /// through the centre of its pixel, is no more than this behind the z-buffer
  /// there (plane_depth_test), or when the point itself is (otherwise) [m].
  /// The plane test is exact for flat triangles, so the tolerance only covers
  /// float rounding and the curvature between neighbouring triangles.
  double depth_tolerance_m = 0.01;
  bool plane_depth_test = true;  ///< compare the point's plane at the pixel centre (needs normals)
  /// Half size of the pixel window of the visibility test: 0 = the point's own
  /// pixel, 1 = any pixel of the 3x3 window (the first version's dilated test).
  int neighbourhood_radius_px = 0;
  /// z-buffer resolution as a multiple of the camera image (when the sizes
  /// below are 0): 2 halves the pixel footprint, so thin parts are resolved.
  int raster_scale = 2;
  int raster_width_px = 0;   ///< z-buffer width [px]; 0 = raster_scale x the image width
  int raster_height_px = 0;  ///< z-buffer height [px]; 0 = raster_scale x the image height
  /// Front-facing test: the angle between the viewing ray and the surface must
  /// be at least this [deg]. Grazing surfaces give stereo no usable texture
  /// and the window of a block matcher straddles them; back faces (negative
  /// angles) are never seen. Below -90 disables the test (needs normals).
  double min_incidence_deg = 15.0;

  /// The first version's loose shell (either camera, 5 cm, 3x3 window, image
  /// raster, no front-facing or plane test), kept for comparisons.
  static ReferenceModelOptions Loose();

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

struct ReferenceModel {
  std::string name;                                  ///< "full" or "shelled"
  std::vector<Eigen::Vector3d> points_in_receiver;   ///< receiver frame [m]
  std::vector<Eigen::Vector3d> normals_in_receiver;  ///< unit outward normals of the points' triangles
};

/// `num_points` points distributed uniformly by area over the mesh surface,
/// deterministic for a given seed on every platform: a triangle is drawn from
/// the cumulative area table, then a point inside it with the square-root
/// barycentric mapping (u = 1 - sqrt(r1), v = sqrt(r1) (1 - r2), w = sqrt(r1) r2).
/// Random reals come from the raw 64-bit output of std::mt19937_64 (53 bits
/// scaled into [0, 1)), never from std::uniform_real_distribution, whose
/// output is implementation-defined. Throws aar::Error on a mesh of zero area.
std::vector<Eigen::Vector3d> SampleSurface(const TriangleMesh& mesh, size_t num_points, uint64_t seed);

/// SampleSurface's points (the same ones) with the unit normal of the
/// triangle each lies on, oriented by the glTF winding (counter-clockwise
/// seen from outside, so outward on a closed mesh).
ReferenceModel SampleSurfaceWithNormals(const TriangleMesh& mesh, size_t num_points, uint64_t seed);

/// The full model: SampleSurface(mesh, options.num_points, options.seed).
ReferenceModel FullModel(const TriangleMesh& mesh, const ReferenceModelOptions& options = {});

/// The pose ShellModel uses: options.tanker_from_receiver or the contact pose.
Eigen::Isometry3d ShellTankerFromReceiver(const StereoRig& rig, const ReferenceModelOptions& options);

/// Visibility of receiver-frame points in one camera, tested against the mesh.
/// The mesh is rasterized into a z-buffer (pinhole model of `intrinsics`
/// scaled to the raster size, pixel centres at integer coordinates, depth along
/// the optical axis interpolated perspective-correctly, i.e. 1/z linear in the
/// image, triangles clipped at `near_m`). A point is visible when it lies in
/// front of the near plane, projects inside the image, and passes the depth
/// test at SOME pixel of the (2r+1)^2 window around its nearest pixel: its
/// depth (or, with plane_depth_test and normals, the depth where its own
/// surface plane meets the ray through that pixel's centre) is no more than
/// depth_tolerance_m behind the z-buffer. With normals, points whose surface
/// makes less than min_incidence_deg with the viewing ray are not visible.
/// `normals_in_receiver` may be empty (no plane or front-facing test) or
/// hold one unit normal per point.
std::vector<bool> VisibleInCamera(const std::vector<Eigen::Vector3d>& points_in_receiver,
                                  const std::vector<Eigen::Vector3d>& normals_in_receiver, const TriangleMesh& mesh,
                                  const Intrinsics& intrinsics, const Eigen::Isometry3d& cam_from_receiver,
                                  double near_m, const ReferenceModelOptions& options = {});

/// The shelled model: the points of `full` visible, by VisibleInCamera, in
/// the cameras options.cameras names, with the receiver at
/// ShellTankerFromReceiver(rig, options); cam_from_receiver =
/// inverse(tanker_from_cam) * tanker_from_receiver. The default (both
/// cameras, own pixel on a 2x raster, plane depth test at 1 cm, surfaces at
/// least 15 deg from grazing) keeps what stereo can reconstruct at the contact
/// position: the thesis's "perspective the tanker's stereo cameras would see".
/// Points keep their order (and normals) from `full`.
ReferenceModel ShellModel(const ReferenceModel& full, const TriangleMesh& mesh, const StereoRig& rig,
                          const ReferenceModelOptions& options = {});

}  // namespace aar
