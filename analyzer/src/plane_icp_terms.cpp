#include "plane_icp_terms.h"

namespace aar::plane_icp_detail {

SensedNoise NoiseAt(const Eigen::Vector3d& point, const StereoNoiseGeometry& g, const PlaneIcpOptions& o) {
  const Eigen::Vector3d offset = point - g.camera_centre_in_tanker;
  const double distance = offset.norm();
  const double depth = std::max(offset.dot(g.optical_axis_in_tanker), 1e-3);
  const double sigma_ray = depth * distance * o.disparity_noise_px / g.focal_times_baseline_px_m;
  const double sigma_lat = depth * o.lateral_noise_px / g.focal_px;
  const double gate = std::max(o.max_correspondence_distance_m, o.gate_sigmas * sigma_ray);
  return {offset / distance, sigma_ray * sigma_ray, sigma_lat * sigma_lat, gate * gate,
          g.focal_times_baseline_px_m / depth};
}

std::vector<SensedNoise> NoiseOf(const std::vector<Eigen::Vector3d>& sensed, const StereoNoiseGeometry& g,
                                 const PlaneIcpOptions& o) {
  std::vector<SensedNoise> noise(sensed.size());
  for (size_t i = 0; i < sensed.size(); ++i) noise[i] = NoiseAt(sensed[i], g, o);
  return noise;
}

Eigen::Vector3d RayLever(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& sensed,
                         const SensedNoise& noise, const StereoNoiseGeometry& geometry) {
  constexpr double kMinCosine = 0.1;
  const double nu = n.dot(noise.ray);
  if (!(std::abs(nu) > kMinCosine)) return sensed;
  const double t = n.dot(p - geometry.camera_centre_in_tanker) / nu;
  return t > 0.0 ? Eigen::Vector3d(geometry.camera_centre_in_tanker + t * noise.ray) : sensed;
}

double UpperMedian(std::vector<double>& v) {
  const auto middle = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), middle, v.end());
  return *middle;
}

void NormalEquations::Add(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& s,
                          const SensedNoise& noise, const Eigen::Vector3d& centre, const PlaneIcpOptions& o,
                          double weight, double& sum_squared, const Eigen::Vector3d& lever) {
  const double r = n.dot(p - s);
  const double along = n.dot(noise.ray);
  const double variance = o.surface_noise_m * o.surface_noise_m + along * along * noise.ray_variance +
                          (1.0 - along * along) * noise.lateral_variance;
  const double scaled = r * r / (o.robust_scale * o.robust_scale * variance);
  const double w = weight / (variance * (1.0 + scaled));  // Cauchy
  Eigen::Matrix<double, 6, 1> j;
  j.head<3>() = (lever - centre).cross(n);
  j.tail<3>() = n;
  Accumulate(j, w, r);
  if (noise_bias) {
    // The gradient of the pair's expected noise term (see PlaneIcpOptions::noise_bias_correction).
    noise_gradient.head<3>() += w * (noise.ray_variance - noise.lateral_variance) * along * noise.ray.cross(n);
    normalized_squares.push_back(r * r / variance);
  }
  sum_squared += r * r;
}

bool NormalEquations::AddDisparity(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& s,
                                   const SensedNoise& noise, const StereoNoiseGeometry& geometry,
                                   const Eigen::Vector3d& centre, const PlaneIcpOptions& o, double weight,
                                   double& sum_squared) {
  const double nu = n.dot(noise.ray);
  if (!(nu < 0.0)) return false;
  const double t = n.dot(p - geometry.camera_centre_in_tanker) / nu;
  const double cos_axis = noise.ray.dot(geometry.optical_axis_in_tanker);
  if (!(t > 0.0) || !(cos_axis > 0.0)) return false;
  const double predicted = geometry.focal_times_baseline_px_m / (t * cos_axis);
  const double per_metre = predicted / t;  // |dD / dt| [px / m]
  const double lateral = t * cos_axis * o.lateral_noise_px / geometry.focal_px;
  const double ray_sigma = o.disparity_noise_px / per_metre;  // sigma_ray at the model's depth [m]
  const double across = o.surface_noise_m * o.surface_noise_m + (1.0 - nu * nu) * lateral * lateral;  // [m^2]
  if (nu * nu * ray_sigma * ray_sigma < across) return false;
  const Eigen::Vector3d x = geometry.camera_centre_in_tanker + t * noise.ray;
  const double r = predicted - noise.disparity;
  const double variance = o.disparity_noise_px * o.disparity_noise_px + per_metre * per_metre * across / (nu * nu);
  const double scaled = r * r / (o.robust_scale * o.robust_scale * variance);
  const double w = weight / (variance * (1.0 + scaled));  // Cauchy
  Eigen::Matrix<double, 6, 1> j;
  j.head<3>() = (x - centre).cross(n);
  j.tail<3>() = n;
  j *= -per_metre / nu;
  Accumulate(j, w, r);
  const double metric = n.dot(p - s);
  sum_squared += metric * metric;
  return true;
}

Eigen::Matrix<double, 6, 1> NormalEquations::NoiseBiasStep(double& scale_squared) {
  constexpr double kChiSquareOneMedian = 0.4549364;
  scale_squared = UpperMedian(normalized_squares) / kChiSquareOneMedian;
  return Solve(scale_squared * noise_gradient);
}

}  // namespace aar::plane_icp_detail
