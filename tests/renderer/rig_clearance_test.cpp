// The tanker (scenes/kc46.glb) never blocks the cameras of any committed rig:
// no tanker triangle reaches into either camera's view (the pyramid through
// the image's edges, for a distorted lens the pinhole pyramid that covers its
// frame), even with the pyramid grown by a margin, and the cameras sit clear
// of the tanker's structure.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "../test_support.h"
#include "aar/lens.h"
#include "aar/renderer/scene_model.h"
#include "aar/rig.h"

namespace aar {
namespace {

using test::SourcePath;

constexpr double kMarginDeg = 2.0;      // the view pyramid grown by this on every side
constexpr double kMinDistanceM = 0.15;  // the camera centres at least this far from any tanker surface
constexpr double kDeg = M_PI / 180.0;

using Triangle = std::array<Eigen::Vector3d, 3>;

std::vector<Triangle> TankerTriangles() {
  const SceneModel tanker = LoadSceneModel(SourcePath("scenes/kc46.glb"));
  std::vector<Triangle> triangles;
  for (const Primitive& p : tanker.primitives) {
    const auto at = [&](uint32_t i) {
      const float* q = p.vertices[i].position;
      return Eigen::Vector3d(q[0], q[1], q[2]);
    };
    for (size_t k = 0; k + 2 < p.indices.size(); k += 3)
      triangles.push_back({at(p.indices[k]), at(p.indices[k + 1]), at(p.indices[k + 2])});
  }
  return triangles;
}

// Tangents of the view's half angles (left, right, top, bottom) in the camera
// frame: the image edges at -0.5 and size - 0.5, through the lens.
std::array<double, 4> ViewTangents(const Intrinsics& k) {
  std::array<double, 4> t = {0, 0, 0, 0};
  const auto edge = [&](double u, double v) {
    Eigen::Vector2d x((u - k.cx_px) / k.fx_px, (v - k.cy_px) / k.fy_px);
    if (!k.distortion.IsZero()) x = *Undistort(k.distortion, x);
    t[0] = std::max(t[0], -x.x());
    t[1] = std::max(t[1], x.x());
    t[2] = std::max(t[2], -x.y());
    t[3] = std::max(t[3], x.y());
  };
  const double u1 = k.width_px - 0.5, v1 = k.height_px - 0.5;
  for (double u = -0.5; u <= u1; u += 1.0) edge(u, -0.5), edge(u, v1);
  for (double v = -0.5; v <= v1; v += 1.0) edge(-0.5, v), edge(u1, v);
  return t;
}

// Whether a triangle (camera frame) meets the pyramid {z > 0, -tl z <= x <= tr z, -tt z <= y <= tb z}:
// Sutherland-Hodgman clipping against its five half spaces.
bool MeetsPyramid(const Triangle& triangle, const std::array<double, 4>& tangent) {
  std::vector<Eigen::Vector3d> poly(triangle.begin(), triangle.end());
  const std::array<Eigen::Vector3d, 5> normals = {Eigen::Vector3d(1, 0, tangent[0]), Eigen::Vector3d(-1, 0, tangent[1]),
                                                  Eigen::Vector3d(0, 1, tangent[2]), Eigen::Vector3d(0, -1, tangent[3]),
                                                  Eigen::Vector3d(0, 0, 1)};
  for (const Eigen::Vector3d& n : normals) {
    std::vector<Eigen::Vector3d> next;
    for (size_t i = 0; i < poly.size(); ++i) {
      const Eigen::Vector3d& a = poly[i];
      const Eigen::Vector3d& b = poly[(i + 1) % poly.size()];
      const double da = n.dot(a) - 1e-9, db = n.dot(b) - 1e-9;
      if (da >= 0) next.push_back(a);
      if ((da >= 0) != (db >= 0)) next.push_back(a + (b - a) * (da / (da - db)));
    }
    poly.swap(next);
    if (poly.empty()) return false;
  }
  return true;
}

// Closest distance from p to a triangle (Ericson, Real-Time Collision Detection, 5.1.5).
double DistanceToTriangle(const Eigen::Vector3d& p, const Triangle& t) {
  const Eigen::Vector3d &a = t[0], &b = t[1], &c = t[2];
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).norm();
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).norm();
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

class TankerClearance : public ::testing::TestWithParam<const char*> {};

TEST_P(TankerClearance, TankerStaysOutOfViewAndClearOfTheCameras) {
  const StereoRig rig = LoadRig(SourcePath(GetParam()));
  static const std::vector<Triangle> tanker = TankerTriangles();
  ASSERT_GT(tanker.size(), 40000u);
  for (const char* side : {"left", "right"}) {
    const Camera& camera = std::string(side) == "left" ? rig.left : rig.right;
    const Eigen::Isometry3d cam_from_tanker = camera.tanker_from_camera.inverse();
    std::vector<Triangle> in_cam;
    double nearest_m = INFINITY;
    for (const Triangle& t : tanker) {
      in_cam.push_back({cam_from_tanker * t[0], cam_from_tanker * t[1], cam_from_tanker * t[2]});
      nearest_m = std::min(nearest_m, DistanceToTriangle(camera.tanker_from_camera.translation(), t));
    }
    const std::array<double, 4> view = ViewTangents(camera.intrinsics);
    // The widest growth of the pyramid (same angle on every side) that the tanker still stays out of.
    const auto free = [&](double grow_deg) {
      std::array<double, 4> grown{};
      for (int i = 0; i < 4; ++i) grown[i] = std::tan(std::atan(view[i]) + grow_deg * kDeg);
      return std::none_of(in_cam.begin(), in_cam.end(), [&](const Triangle& t) { return MeetsPyramid(t, grown); });
    };
    ASSERT_TRUE(free(0.0)) << GetParam() << " " << side << ": the tanker is inside the camera's view";
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 20; ++i) (free(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
    std::printf("%s %s: tanker clears the view by %.2f deg on every side; nearest tanker surface %.3f m\n", GetParam(),
                side, lo, nearest_m);
    EXPECT_GE(lo, kMarginDeg) << GetParam() << " " << side;
    EXPECT_GE(nearest_m, kMinDistanceM) << GetParam() << " " << side;
  }
}

INSTANTIATE_TEST_SUITE_P(CommittedRigs, TankerClearance, test::kCommittedRigs, test::CommittedRigName);

}  // namespace
}  // namespace aar
