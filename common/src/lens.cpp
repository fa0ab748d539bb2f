#include "aar/lens.h"

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <vector>

#include "aar/error.h"
#include "aar/text.h"

namespace aar {
namespace {

constexpr double kNewtonTolerance = 1e-13;  // normalized units: 1e-10 px at f = 900 px
constexpr int kNewtonSteps = 50;
constexpr double kMaxOffAxisDeg = 60.0;

// g(r) = r (1 + k1 r^2 + k2 r^4 + k3 r^6); g'(r) as a cubic in s = r^2.
double RadialSlope(const BrownConrady& l, double s) {
  return 1.0 + s * (3.0 * l.k1 + s * (5.0 * l.k2 + s * 7.0 * l.k3));
}

// The largest r^2 up to which the radial mapping increases (capped at 1e4).
double FoldRadiusSquared(const BrownConrady& lens) {
  double lo = 0.0, hi = 1e4;
  if (RadiallyMonotonic(lens, hi)) return hi;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (RadiallyMonotonic(lens, mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

Eigen::Vector2d Distort(const BrownConrady& l, const Eigen::Vector2d& u) {
  const double x = u.x(), y = u.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (l.k1 + r2 * (l.k2 + r2 * l.k3));
  return {x * radial + 2.0 * l.p1 * x * y + l.p2 * (r2 + 2.0 * x * x),
          y * radial + l.p1 * (r2 + 2.0 * y * y) + 2.0 * l.p2 * x * y};
}

Eigen::Matrix2d DistortJacobian(const BrownConrady& l, const Eigen::Vector2d& u) {
  const double x = u.x(), y = u.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (l.k1 + r2 * (l.k2 + r2 * l.k3));
  const double d_radial = 2.0 * (l.k1 + r2 * (2.0 * l.k2 + r2 * 3.0 * l.k3));  // d(radial)/dx = x d_radial
  Eigen::Matrix2d j;
  j(0, 0) = radial + x * x * d_radial + 2.0 * l.p1 * y + 6.0 * l.p2 * x;
  j(0, 1) = x * y * d_radial + 2.0 * l.p1 * x + 2.0 * l.p2 * y;
  j(1, 0) = x * y * d_radial + 2.0 * l.p1 * x + 2.0 * l.p2 * y;
  j(1, 1) = radial + y * y * d_radial + 6.0 * l.p1 * y + 2.0 * l.p2 * x;
  return j;
}

bool RadiallyMonotonic(const BrownConrady& l, double r2) {
  if (!(r2 >= 0.0)) return false;
  if (RadialSlope(l, r2) <= 0.0) return false;
  // Interior minima of the slope: roots of 3 k1 + 10 k2 s + 21 k3 s^2.
  std::vector<double> roots;
  const double a = 21.0 * l.k3, b = 10.0 * l.k2, c = 3.0 * l.k1;
  if (a == 0.0) {
    if (b != 0.0) roots.push_back(-c / b);
  } else {
    const double disc = b * b - 4.0 * a * c;
    if (disc >= 0.0) {
      roots.push_back((-b - std::sqrt(disc)) / (2.0 * a));
      roots.push_back((-b + std::sqrt(disc)) / (2.0 * a));
    }
  }
  for (double s : roots) {
    if (s > 0.0 && s < r2 && RadialSlope(l, s) <= 0.0) return false;
  }
  return true;
}

std::optional<Eigen::Vector2d> Undistort(const BrownConrady& lens, const Eigen::Vector2d& distorted) {
  Eigen::Vector2d x = distorted;
  for (int step = 0; step < kNewtonSteps; ++step) {
    const Eigen::Vector2d residual = Distort(lens, x) - distorted;
    if (residual.lpNorm<Eigen::Infinity>() < kNewtonTolerance) {
      if (!RadiallyMonotonic(lens, x.squaredNorm())) return std::nullopt;
      return x;
    }
    const Eigen::Matrix2d j = DistortJacobian(lens, x);
    if (!(j.determinant() > 0.0)) return std::nullopt;
    x -= j.inverse() * residual;
    if (!x.allFinite()) return std::nullopt;
  }
  return std::nullopt;
}

void CheckDistortionInImage(const BrownConrady& lens, double fx, double fy, double cx, double cy, int width, int height,
                            const std::string& where) {
  if (lens.IsZero()) return;
  const std::string prefix = where + ": lens distortion (" + DescribeDistortion(lens) + ") ";
  const double max_r = std::tan(kMaxOffAxisDeg * M_PI / 180.0);
  const auto check = [&](double u, double v) {
    const Eigen::Vector2d distorted((u - cx) / fx, (v - cy) / fy);
    const std::optional<Eigen::Vector2d> x = Undistort(lens, distorted);
    const std::string at = "at pixel (" + FormatFixed(u, 1) + ", " + FormatFixed(v, 1) + ")";
    if (!x) {
      const double fold_r = std::sqrt(FoldRadiusSquared(lens));
      const double reach = Distort(lens, Eigen::Vector2d(fold_r, 0.0)).x();
      throw Error(prefix + "is not one-to-one inside the image: no undistorted ray maps to " + at +
                  "; the radial mapping stops increasing at r = " + FormatFixed(fold_r, 3) + " (" +
                  FormatFixed(reach * fx, 0) + " px from the principal point), the pixel is " +
                  FormatFixed(distorted.norm() * fx, 0) + " px from it");
    }
    if (x->norm() > max_r) {
      throw Error(prefix + "needs rays more than " + FormatFixed(kMaxOffAxisDeg, 0) + " deg off axis " + at);
    }
    if (!(DistortJacobian(lens, *x).determinant() > 0.0)) {
      throw Error(prefix + "folds the image over " + at + " (the mapping's Jacobian is not positive there)");
    }
  };
  const double u0 = -0.5, u1 = width - 0.5, v0 = -0.5, v1 = height - 0.5;
  for (double u = u0; u <= u1; u += 0.5) {
    check(u, v0);
    check(u, v1);
  }
  for (double v = v0; v <= v1; v += 0.5) {
    check(u0, v);
    check(u1, v);
  }
  for (int v = 0; v < height; v += 8) {
    for (int u = 0; u < width; u += 8) check(u, v);
  }
}

std::string DescribeDistortion(const BrownConrady& l) {
  const auto num = [](double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.6g", value);
    return std::string(buffer);
  };
  return "k1 " + num(l.k1) + ", k2 " + num(l.k2) + ", p1 " + num(l.p1) + ", p2 " + num(l.p2) + ", k3 " + num(l.k3);
}

}  // namespace aar
