#include "geometry.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <utility>

#include "aar/error.h"

namespace aar::scenes {

Profile::Profile(std::vector<double> x, std::vector<double> y) : x_(std::move(x)), y_(std::move(y)) {
  const std::size_t n = x_.size();
  if (n < 2 || y_.size() != n) throw Error("Profile: need >= 2 matching points");
  std::vector<double> secant(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    if (!(x_[i + 1] > x_[i])) throw Error("Profile: x must ascend strictly");
    secant[i] = (y_[i + 1] - y_[i]) / (x_[i + 1] - x_[i]);
  }
  // Fritsch-Carlson: harmonic-mean slopes at interior points, zero at extrema.
  slope_.assign(n, 0.0);
  slope_[0] = secant[0];
  slope_[n - 1] = secant[n - 2];
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double a = secant[i - 1], b = secant[i];
    if (a * b <= 0.0) continue;
    const double wa = 2.0 * (x_[i + 1] - x_[i]) + (x_[i] - x_[i - 1]);
    const double wb = (x_[i + 1] - x_[i]) + 2.0 * (x_[i] - x_[i - 1]);
    slope_[i] = (wa + wb) / (wa / a + wb / b);
  }
}

double Profile::operator()(double x) const {
  if (x <= x_.front()) return y_.front();
  if (x >= x_.back()) return y_.back();
  const auto it = std::upper_bound(x_.begin(), x_.end(), x);
  const std::size_t i = static_cast<std::size_t>(it - x_.begin()) - 1;
  const double h = x_[i + 1] - x_[i];
  const double t = (x - x_[i]) / h;
  const double t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * y_[i] + (t3 - 2 * t2 + t) * h * slope_[i] + (-2 * t3 + 3 * t2) * y_[i + 1] +
         (t3 - t2) * h * slope_[i + 1];
}

void Mesh::AddQuad(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& normal) {
  const auto base = static_cast<std::uint32_t>(positions.size());
  for (const Vec3* p : {&p0, &p1, &p2, &p3}) {
    positions.push_back(*p);
    normals.push_back(normal.normalized());
  }
  const bool ccw = (p1 - p0).cross(p2 - p0).dot(normal) > 0.0;
  const std::uint32_t order[6] = {0, 1, 2, 0, 2, 3};
  const std::uint32_t flipped[6] = {0, 2, 1, 0, 3, 2};
  for (std::uint32_t k : (ccw ? order : flipped)) indices.push_back(base + k);
}

Vec3 Patch::Normal(double u, double v) const {
  constexpr double h = 1e-4;
  auto wrap_or_clamp = [&](double t) {
    if (periodic_v) return t - std::floor(t);
    return std::clamp(t, 0.0, 1.0);
  };
  auto cross_at = [&](double uu) {
    const Vec3 du = point(std::min(uu + h, 1.0), v) - point(std::max(uu - h, 0.0), v);
    const Vec3 dv = point(uu, wrap_or_clamp(v + h)) - point(uu, wrap_or_clamp(v - h));
    return Vec3(du.cross(dv));
  };
  Vec3 n = cross_at(u);
  if (n.norm() < 1e-14) n = cross_at(std::clamp(u, 2e-3, 1.0 - 2e-3));  // pole
  return n.normalized();
}

Mesh Tessellate(const Patch& patch, const AtlasRect* rect) {
  Mesh mesh;
  const std::size_t nu = patch.u_samples.size(), nv = patch.v_samples.size();
  mesh.positions.reserve(nu * nv);
  mesh.normals.reserve(nu * nv);
  for (double u : patch.u_samples) {
    for (double v : patch.v_samples) {
      mesh.positions.push_back(patch.point(u, v));
      mesh.normals.push_back(patch.Normal(u, v));
      if (rect != nullptr) {
        mesh.uvs.emplace_back((rect->x0 + u * rect->width) / rect->atlas_width,
                              (rect->y0 + v * rect->height) / rect->atlas_height);
      }
    }
  }
  auto index = [nv](std::size_t i, std::size_t j) { return static_cast<std::uint32_t>(i * nv + j); };
  auto add_triangle = [&mesh](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const Vec3& pa = mesh.positions[a];
    if ((mesh.positions[b] - pa).cross(mesh.positions[c] - pa).squaredNorm() == 0.0) return;
    mesh.indices.insert(mesh.indices.end(), {a, b, c});
  };
  for (std::size_t i = 0; i + 1 < nu; ++i) {
    for (std::size_t j = 0; j + 1 < nv; ++j) {
      const auto a = index(i, j), b = index(i + 1, j), c = index(i + 1, j + 1), d = index(i, j + 1);
      add_triangle(a, b, c);
      add_triangle(a, c, d);
    }
  }
  return mesh;
}

Box3 BoundingBox(const std::vector<Vec3>& points) {
  Box3 box{Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)};
  for (const Vec3& p : points) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

double SignedVolume(const Mesh& mesh) {
  double six_v = 0.0;
  for (std::size_t k = 0; k < mesh.indices.size(); k += 3) {
    const Vec3& a = mesh.positions[mesh.indices[k]];
    const Vec3& b = mesh.positions[mesh.indices[k + 1]];
    const Vec3& c = mesh.positions[mesh.indices[k + 2]];
    six_v += a.dot(b.cross(c));
  }
  return six_v / 6.0;
}

double SurfaceArea(const Mesh& mesh) {
  double area = 0.0;
  for (std::size_t k = 0; k < mesh.indices.size(); k += 3) {
    const Vec3& a = mesh.positions[mesh.indices[k]];
    area += 0.5 * (mesh.positions[mesh.indices[k + 1]] - a).cross(mesh.positions[mesh.indices[k + 2]] - a).norm();
  }
  return area;
}

TexelDensity MeasureTexelDensity(const Mesh& mesh, int atlas_width, int atlas_height, double threshold_per_m) {
  std::vector<std::pair<double, double>> samples;  // (texels per metre, area)
  double total_area = 0.0;
  for (std::size_t k = 0; k < mesh.indices.size(); k += 3) {
    const std::uint32_t ia = mesh.indices[k], ib = mesh.indices[k + 1], ic = mesh.indices[k + 2];
    const Vec3 e1 = mesh.positions[ib] - mesh.positions[ia];
    const Vec3 e2 = mesh.positions[ic] - mesh.positions[ia];
    const double area = 0.5 * e1.cross(e2).norm();
    if (area < 1e-10) continue;
    // Orthonormal basis of the triangle's plane, then the 2x2 map metres -> texels.
    const Vec3 t1 = e1.normalized();
    const Vec3 t2 = e1.cross(e2).cross(e1).normalized();
    Eigen::Matrix2d world;
    world << e1.dot(t1), e2.dot(t1), e1.dot(t2), e2.dot(t2);
    const Vec2 scale(atlas_width, atlas_height);
    const Vec2 d1 = (mesh.uvs[ib] - mesh.uvs[ia]).cwiseProduct(scale);
    const Vec2 d2 = (mesh.uvs[ic] - mesh.uvs[ia]).cwiseProduct(scale);
    Eigen::Matrix2d texels;
    texels << d1.x(), d2.x(), d1.y(), d2.y();
    const Eigen::Matrix2d jacobian = texels * world.inverse();
    const double density = Eigen::JacobiSVD<Eigen::Matrix2d>(jacobian).singularValues()(1);
    samples.emplace_back(density, area);
    total_area += area;
  }
  std::sort(samples.begin(), samples.end());
  TexelDensity result;
  double cumulative = 0.0;
  for (const auto& [density, area] : samples) {
    if (density < threshold_per_m) result.share_below += area / total_area;
    const double before = cumulative;
    cumulative += area / total_area;
    if (before < 0.01 && cumulative >= 0.01) result.p01_per_m = density;
    if (before < 0.5 && cumulative >= 0.5) result.median_per_m = density;
  }
  return result;
}

std::vector<double> UniformSamples(int segments) {
  std::vector<double> s(static_cast<std::size_t>(segments) + 1);
  for (int i = 0; i <= segments; ++i) s[static_cast<std::size_t>(i)] = static_cast<double>(i) / segments;
  return s;
}

}  // namespace aar::scenes
