#pragma once
// Point-to-point ICP (thesis section 3.6; Besl and McKay 1992) estimating
// tanker_from_receiver: the rigid transform that moves the reference model
// (receiver frame) onto the sensed point cloud (tanker frame). Each iteration
// pairs points with their nearest neighbour (nanoflann KD-tree) and solves
// the closed-form least-squares rotation and translation (Kabsch / Umeyama
// without scale, SVD of the 3x3 cross-covariance).
//
// Everything is single-threaded, sums run in a fixed order in double
// precision, so a result is bitwise repeatable for the same inputs.

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "aar/analyzer/kdtree.h"
#include "aar/analyzer/registration.h"

namespace aar {

/// Direction of the nearest-neighbour pairing.
enum class IcpCorrespondence {
  /// Each (transformed) model point is paired with its nearest sensed point;
  /// KD-tree over the sensed cloud, built once per frame. The thesis's
  /// direction ("converge the reference point cloud to the sensed point
  /// cloud"). Model points that the cameras did not see in this frame (tail
  /// out of view, the far side in the full model) still pull on the estimate.
  kModelToSensed,
  /// Each sensed point is paired with its nearest model point; KD-tree over
  /// the model, built once per model and reused across frames. Every pair is
  /// then a surface actually sensed, so unseen model parts do not bias the
  /// pose; stereo outliers pull instead (use max_correspondence_distance_m).
  kSensedToModel,
};

/// "model_to_sensed" / "sensed_to_model"; the parser throws aar::Error on other text.
std::string ToString(IcpCorrespondence correspondence);
IcpCorrespondence ParseIcpCorrespondence(const std::string& text);

struct IcpOptions {
  int max_iterations = 30;  ///< transform updates at most (thesis 3.7: 30)
  /// Converged when |mse_prev - mse| / mse_prev < this (mean squared
  /// correspondence distance, before the update of an iteration).
  double relative_mse_tolerance = 1e-6;
  /// Converged when one update moves less than both of these.
  double translation_tolerance_m = 1e-5;  ///< [m]
  double rotation_tolerance_rad = 1e-5;   ///< [rad]
  /// Pairs farther apart are ignored (outlier rejection). Default: infinity,
  /// every pair counts, as in the thesis's plain point-to-point ICP.
  double max_correspondence_distance_m = std::numeric_limits<double>::infinity();  ///< [m]
  IcpCorrespondence correspondence = IcpCorrespondence::kModelToSensed;
  int kdtree_leaf_size = 10;  ///< nanoflann leaf size [points]
  /// Skip the KD-tree when a point's previous nearest neighbour provably still
  /// is its nearest (see icp.cpp); exact, same pairs as without it (up to ties
  /// between equidistant points), several times faster in late iterations.
  bool cache_nearest = true;

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

/// ICP against one reference model, reusable across frames (and threads).
/// For kSensedToModel the model's KD-tree is built once, here.
class IcpRegistration : public RegistrationMethod {
 public:
  IcpRegistration(std::vector<Eigen::Vector3d> model_points_in_receiver, const IcpOptions& options = {});
  ~IcpRegistration() override;

  /// Registers one frame. Throws aar::Error when either cloud is empty.
  RegistrationResult Register(const std::vector<Eigen::Vector3d>& sensed_points_in_tanker,
                              const Eigen::Isometry3d& initial_tanker_from_receiver) const override;

  const std::vector<Eigen::Vector3d>& model_points_in_receiver() const override { return model_; }
  const IcpOptions& options() const { return options_; }

 private:
  std::vector<Eigen::Vector3d> model_;
  IcpOptions options_;
  std::unique_ptr<KdTree3d> model_tree_;  // kSensedToModel only
};

/// One-shot form of IcpRegistration(model, options).Register(sensed, initial).
RegistrationResult RegisterIcp(const std::vector<Eigen::Vector3d>& model_points_in_receiver,
                               const std::vector<Eigen::Vector3d>& sensed_points_in_tanker,
                               const Eigen::Isometry3d& initial_tanker_from_receiver, const IcpOptions& options = {});

/// The thesis's seed (section 3.7, Experiment 1): zero roll, pitch and yaw,
/// and the model's centroid placed on the sensed cloud's centroid:
/// translation = centroid(sensed) - centroid(model). Throws aar::Error when a
/// cloud is empty.
Eigen::Isometry3d InitialGuessAtCentroid(const std::vector<Eigen::Vector3d>& sensed_points_in_tanker,
                                         const std::vector<Eigen::Vector3d>& model_points_in_receiver);

/// The least-squares rigid transform b_from_a minimising sum |b_from_a * a_i - b_i|^2
/// (Kabsch / Umeyama without scale; reflections excluded). Needs >= 3 pairs
/// not all collinear for a unique rotation.
Eigen::Isometry3d RigidTransformFromPairs(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b);

}  // namespace aar
