#pragma once
// Brown-Conrady lens distortion, OpenCV's five-coefficient model (k1, k2, p1,
// p2, k3; docs/dataset-format.md, rig.json). On normalized image coordinates
// x = X/Z, y = Y/Z of the ideal pinhole, r^2 = x^2 + y^2:
//   x_d = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
//   y_d = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y
// and the pixel is (fx x_d + cx, fy y_d + cy), as in cv::projectPoints.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>

namespace aar {

struct BrownConrady {
  double k1 = 0.0;  ///< radial, r^2 term
  double k2 = 0.0;  ///< radial, r^4 term
  double p1 = 0.0;  ///< tangential (decentring)
  double p2 = 0.0;  ///< tangential (decentring)
  double k3 = 0.0;  ///< radial, r^6 term

  /// All five coefficients zero: the ideal pinhole (the renderer's exact path).
  bool IsZero() const { return k1 == 0.0 && k2 == 0.0 && p1 == 0.0 && p2 == 0.0 && k3 == 0.0; }
  /// OpenCV's order (distCoeffs 1x5): k1, k2, p1, p2, k3.
  std::array<double, 5> OpenCvOrder() const { return {k1, k2, p1, p2, k3}; }
  bool operator==(const BrownConrady&) const = default;
};

/// Distorted normalized coordinates of undistorted ones (the formula above).
Eigen::Vector2d Distort(const BrownConrady& lens, const Eigen::Vector2d& undistorted);

/// d(distorted) / d(undistorted), 2x2.
Eigen::Matrix2d DistortJacobian(const BrownConrady& lens, const Eigen::Vector2d& undistorted);

/// Whether the radial factor r (1 + k1 r^2 + k2 r^4 + k3 r^6) increases on all
/// of [0, sqrt(r2)]: exact (the minimum of its derivative, a cubic in r^2, is
/// at an end or at a root of its quadratic derivative). Beyond, the model
/// folds back and a far point can land inside the image.
bool RadiallyMonotonic(const BrownConrady& lens, double r2);

/// The undistorted normalized coordinates whose distortion is `distorted`:
/// Newton's method from `distorted`, to 1e-13 (normalized units); nullopt when
/// it does not converge in 50 steps or leaves the radially monotonic range.
std::optional<Eigen::Vector2d> Undistort(const BrownConrady& lens, const Eigen::Vector2d& distorted);

/// Throws aar::Error prefixed by `where` unless the lens maps a region of the
/// pinhole image one-to-one onto the whole width x height image (pixel edges
/// at -0.5 and width - 0.5): every pixel corner, edge midpoint and every 8th
/// pixel centre has an undistorted preimage, inside the radially monotonic
/// range, with a positive Jacobian determinant, and that preimage is at most
/// 60 deg off axis. The message gives the reason (e.g. where the radial
/// mapping stops increasing against the radius the image corner needs).
void CheckDistortionInImage(const BrownConrady& lens, double fx_px, double fy_px, double cx_px, double cy_px,
                            int width_px, int height_px, const std::string& where);

/// "k1 -0.15, k2 0.05, p1 0.0001, p2 -0.0001, k3 0" for messages and logs.
std::string DescribeDistortion(const BrownConrady& lens);

}  // namespace aar
