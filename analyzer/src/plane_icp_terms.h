#pragma once
// The terms of the point-to-plane ICP's Gauss-Newton steps (plane_icp.cpp):
// the stereo noise model of each sensed point and the normal equations its
// residuals (metric, along the ray, or in disparity) add to. Private to the
// registration; plane_icp.h has the options they follow.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "aar/analyzer/plane_icp.h"

namespace aar::plane_icp_detail {

// Per sensed point: the noise model's variances along and across its ray.
struct SensedNoise {
  Eigen::Vector3d ray;      // unit viewing ray in the tanker frame
  double ray_variance;      // sigma_ray^2 [m^2]
  double lateral_variance;  // sigma_lat^2 [m^2]
  double gate_squared;      // pairs farther than sqrt(this) are ignored [m^2]
  double disparity;         // the disparity the point was re-projected from, f b / depth [px]
};

// The noise model at `point` (tanker frame), seen from the left camera.
SensedNoise NoiseAt(const Eigen::Vector3d& point, const StereoNoiseGeometry& g, const PlaneIcpOptions& o);

std::vector<SensedNoise> NoiseOf(const std::vector<Eigen::Vector3d>& sensed, const StereoNoiseGeometry& g,
                                 const PlaneIcpOptions& o);

// kMetricRay's lever arm: where the sensed point's ray meets the model's tangent plane (p, n); the sensed point
// where the ray grazes the plane or meets it behind the camera.
Eigen::Vector3d RayLever(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& sensed,
                         const SensedNoise& noise, const StereoNoiseGeometry& geometry);

// The element at v.size() / 2 in sorted order (reorders v).
double UpperMedian(std::vector<double>& v);

// Normal equations of one Gauss-Newton step in the frame centred on `centre`.
struct NormalEquations {
  Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
  // PlaneIcpOptions::noise_bias_correction: the noise term's gradient and
  // each pair's r^2 / sigma^2, gathered by Add when noise_bias is set.
  bool noise_bias = false;
  Eigen::Matrix<double, 6, 1> noise_gradient = Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<double> normalized_squares;

  // Residual r = n . (p - s) of a model point p (tanker frame, normal n) and a
  // sensed point s; Jacobian [ (s - centre) x n, n ] for the perturbation
  // p -> centre + (I + [w]x)(p - centre) + v (normal rotated with it).
  // `lever`: the point the rotation turns the residual about (s: the exact
  // Jacobian; the model point p: free of the sensed point's noise).
  void Add(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& s, const SensedNoise& noise,
           const Eigen::Vector3d& centre, const PlaneIcpOptions& o, double weight, double& sum_squared,
           const Eigen::Vector3d& lever);

  // kDisparity: the residual along the sensed point's own ray. The model's
  // tangent plane (p, n) meets the ray c + t u at t = n . (p - c) / (n . u),
  // x = c + t u, where the model predicts the disparity D = f b / (t (u . a))
  // (a the optical axis; the rectified one differs by the rectification's
  // turn, well under a degree, which scales D and d alike by under 1e-4);
  // r = D - d with d = f b / (s - c) . a the measured disparity.
  // dt = [ (x - centre) x n, n ] . (w, v) / (n . u), so the lever arm is x,
  // on the model's surface, not the noisy s (no errors in the variables),
  // and r, unlike a distance in metres, has the measurement's own symmetric
  // noise: sigma_r^2 = sigma_d^2 + (D / t)^2 (sigma_0^2 + (1 - (n.u)^2)
  // sigma_lat^2) / (n.u)^2, every term from the model's depth, none from the
  // noisy one. Where the plane is so oblique to the ray that the lateral and
  // surface terms outweigh the depth noise's, (n.u)^2 sigma_ray^2 < sigma_0^2
  // + (1 - (n.u)^2) sigma_lat^2, the depth noise hardly enters the metric
  // residual, whose meeting point would instead swing far along the ray with
  // any lateral error: false, and the caller adds the metric residual.
  bool AddDisparity(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& s,
                    const SensedNoise& noise, const StereoNoiseGeometry& geometry, const Eigen::Vector3d& centre,
                    const PlaneIcpOptions& o, double weight, double& sum_squared);

  // One residual r with Jacobian j and weight w. The upper triangle of h only
  // (h is symmetric; Solve mirrors it), each term (w j_a) j_b as the full
  // outer product would form it.
  void Accumulate(const Eigen::Matrix<double, 6, 1>& j, double w, double r) {
    const Eigen::Matrix<double, 6, 1> wj = w * j;
    for (int b = 0; b < 6; ++b) {
      for (int a = 0; a <= b; ++a) h(a, b) += wj(a) * j(b);
    }
    g.noalias() += w * r * j;
  }

  Eigen::Matrix<double, 6, 1> Solve() { return Solve(g); }
  Eigen::Matrix<double, 6, 1> Solve(const Eigen::Matrix<double, 6, 1>& gradient) {
    h.triangularView<Eigen::StrictlyLower>() = h.transpose();
    return -h.ldlt().solve(gradient);
  }

  // The step against the noise's own term with the variances scaled by
  // scale_squared = median(r^2 / sigma^2) / (chi-square(1)'s median).
  Eigen::Matrix<double, 6, 1> NoiseBiasStep(double& scale_squared);
};

}  // namespace aar::plane_icp_detail
