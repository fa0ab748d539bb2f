// Geometry primitives shared by the scene generator: interpolated profiles,
// parametric surface patches and their tessellation into indexed triangle
// meshes. Everything here is in body axes (x forward, y left, z up, metres);
// the conversion to glTF axes happens only when a file is written.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <cstdint>
#include <functional>
#include <vector>

namespace aar::scenes {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

/// Smooth, shape-preserving interpolation of a tabulated function y(x):
/// monotone piecewise cubic Hermite (Fritsch-Carlson), so a profile never
/// overshoots its table. Outside the table the end values are held.
class Profile {
 public:
  Profile() = default;
  /// `x` strictly ascending, same length as `y`, at least two points.
  Profile(std::vector<double> x, std::vector<double> y);
  double operator()(double x) const;

 private:
  std::vector<double> x_, y_, slope_;
};

/// Indexed triangle mesh in body axes.
struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;           ///< unit, pointing out of the solid
  std::vector<Vec2> uvs;               ///< empty when untextured; glTF convention, (0,0) = top-left texel corner
  std::vector<std::uint32_t> indices;  ///< counter-clockwise seen from outside (glTF front faces)

  std::size_t TriangleCount() const { return indices.size() / 3; }
  /// Appends a planar quad p0..p3 (any winding) with a flat `normal`; the
  /// triangles are wound counter-clockwise seen from the side `normal` points to.
  void AddQuad(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& normal);
};

/// A parametric surface patch P(u, v), u and v in [0, 1], body axes.
/// Convention: dP/du x dP/dv points out of the solid, so the tessellated
/// triangles face outward.
struct Patch {
  std::function<Vec3(double u, double v)> point;
  std::vector<double> u_samples;  ///< vertex rows, ascending, first 0 and last 1
  std::vector<double> v_samples;  ///< vertex columns, ascending, first 0 and last 1
  bool periodic_v = false;        ///< closed sections: P(u, 0) == P(u, 1)
  double length_u_m = 0.0;        ///< upper bound of the surface arc length along u (texture allocation)
  double length_v_m = 0.0;        ///< upper bound of the surface arc length along v

  /// Outward unit normal from central differences; at poles (where the
  /// surface degenerates to a point) the normal of the nearest ring is used.
  Vec3 Normal(double u, double v) const;
};

/// Where a patch's (u, v) square lands in a texture atlas, in texels:
/// texel column = x0 + u * width, texel row = y0 + v * height.
struct AtlasRect {
  double x0 = 0, y0 = 0, width = 0, height = 0;
  int atlas_width = 0, atlas_height = 0;
};

/// Tessellates a patch on its sample grid (two triangles per cell, exactly
/// degenerate triangles at poles dropped). Texture coordinates are written
/// when `rect` is given.
Mesh Tessellate(const Patch& patch, const AtlasRect* rect);

struct Box3 {
  Vec3 min, max;
  Vec3 size() const { return max - min; }
};

Box3 BoundingBox(const std::vector<Vec3>& points);
/// Signed enclosed volume (divergence theorem); positive for a closed mesh
/// with outward-facing triangles.
double SignedVolume(const Mesh& mesh);
double SurfaceArea(const Mesh& mesh);

/// Texel density statistics of a textured mesh: for every non-degenerate
/// triangle the smaller singular value of the metres-to-texels map, i.e. the
/// worst-direction texels per metre.
struct TexelDensity {
  double p01_per_m = 0;     ///< area-weighted 1st percentile
  double median_per_m = 0;  ///< area-weighted median
  double share_below = 0;   ///< fraction of the surface area below `threshold_per_m`
};
TexelDensity MeasureTexelDensity(const Mesh& mesh, int atlas_width, int atlas_height, double threshold_per_m);

/// n + 1 samples 0, 1/n, ..., 1.
std::vector<double> UniformSamples(int segments);

/// glTF axes from body axes: X_gltf = y_body, Y_gltf = z_body, Z_gltf = x_body
/// (the inverse of docs/frames.md's body_from_gltf; a proper rotation, so
/// winding and normals carry over unchanged).
inline Vec3 GltfFromBody(const Vec3& p) { return {p.y(), p.z(), p.x()}; }

}  // namespace aar::scenes
