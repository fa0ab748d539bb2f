#pragma once
// The registration interface: a method that finds tanker_from_receiver, the
// rigid transform moving a reference model (receiver frame) onto a sensed
// cloud (tanker frame), from an initial transform. Point-to-point ICP
// (icp.h) and point-to-plane ICP (plane_icp.h) implement it; the frame
// pipeline holds one and calls it without knowing which.

#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

namespace aar {

/// What every registration method returns.
struct RegistrationResult {
  Eigen::Isometry3d tanker_from_receiver = Eigen::Isometry3d::Identity();
  bool converged = false;       ///< the tolerances were met before max_iterations
  int iterations = 0;           ///< transform updates applied
  size_t num_inliers = 0;       ///< pairs within the method's correspondence limit at the returned transform
  double rmse_m = 0.0;          ///< RMS residual of those pairs at the returned transform [m]
  double fitness = 0.0;         ///< num_inliers / the points that looked for a partner
  double initial_rmse_m = 0.0;  ///< the same RMS at the initial transform [m]
  /// Point-to-plane with noise_bias_correction: the pairs' noise against the
  /// model's, sqrt(median(r^2 / sigma^2) / 0.4549) (1 = as modelled; 0 = not
  /// applied, and for every other method).
  double noise_scale = 0.0;
};

/// A registration method against one reference model, reusable across
/// frames (and threads: Register is const).
class RegistrationMethod {
 public:
  virtual ~RegistrationMethod() = default;

  /// Registers one frame's sensed cloud from `initial_tanker_from_receiver`.
  /// Throws aar::Error when a cloud is empty or not finite.
  virtual RegistrationResult Register(const std::vector<Eigen::Vector3d>& sensed_points_in_tanker,
                                      const Eigen::Isometry3d& initial_tanker_from_receiver) const = 0;

  /// The reference model's points (receiver frame).
  virtual const std::vector<Eigen::Vector3d>& model_points_in_receiver() const = 0;
};

}  // namespace aar
