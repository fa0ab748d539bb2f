#pragma once
// Removing the receiver's propeller discs from a sensed cloud
// (docs/analysis.md, "Propellers"). A spinning propeller is a blurred
// disc in front of the wings and engines: its points belong to no surface of
// the reference model, and there are so many of them that the robust kernel
// does not reject them. The tanker knows the receiver's type, so it knows
// where the discs are on the airframe (common/include/aar/propeller.h);
// under a registered pose they are two discs in the tanker frame, and the
// points on them (inside a cylinder about each disc) or seen through them
// (behind a disc, their ray crossing it: the wing and engine behind a
// half-transparent blur give mixed disparities) are dropped before the pose
// is registered again.

#include <Eigen/Geometry>
#include <vector>

namespace aar {

struct PropellerMaskOptions {
  /// Added to the blade tip radius (1.25 m): the registration's error
  /// across the axis, and the blur of the disc's edge [m].
  double radial_margin_m = 0.15;
  /// Half the cylinder's length along the axis, about the blade plane [m]:
  /// the blades' own depth (+-0.09 m), the registration's error along the
  /// axis and the stereo noise along the ray.
  double axial_half_width_m = 0.6;
  /// The same for the first pass, from the estimate made with the discs in
  /// the cloud, which they pull forward (by up to about 1 m in region B) [m].
  double first_axial_half_width_m = 2.0;
  /// Mask and register again this many times, each from the last estimate.
  int passes = 3;

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

/// The points of `sensed_in_tanker` neither inside a disc's cylinder nor
/// behind a disc on a ray from `camera_in_tanker` that crosses it, with the
/// receiver at `tanker_from_receiver`, in their order; `removed` (optional)
/// receives how many were inside. `axial_half_width_m` is the options' for
/// the pass (axial_half_width_m or first_axial_half_width_m).
std::vector<Eigen::Vector3d> OutsidePropellerDiscs(const std::vector<Eigen::Vector3d>& sensed_in_tanker,
                                                   const Eigen::Isometry3d& tanker_from_receiver,
                                                   const Eigen::Vector3d& camera_in_tanker,
                                                   const PropellerMaskOptions& options, double axial_half_width_m,
                                                   size_t* removed = nullptr);

/// Whether the pose `registered`, found from the cloud masked with the
/// receiver at `masked_at`, still puts the discs in that mask: along the
/// axis, every point of both discs' rims within `axial_half_width_m` (the
/// cylinder's half-length) of where the mask put it, and across it, each
/// hub within a disc radius (the mask still covers the disc's centre). A
/// registration that moves a disc off its mask removed points by a pose it
/// no longer agrees with: the first estimate too far off, or too few points
/// left to hold the pose, as at long range where it flips.
bool PropellerMaskAgrees(const Eigen::Isometry3d& masked_at, const Eigen::Isometry3d& registered,
                         double axial_half_width_m);

}  // namespace aar
