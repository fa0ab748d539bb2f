// The rectangle that can hold geometry (geometry_rect.h): conservative for
// triangles that reach behind the camera, tight where their visible part is
// known, and empty for the tanker from the cameras of every committed rig
// (whose bounding box contains the cameras).

#include "aar/renderer/geometry_rect.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "../test_support.h"
#include "aar/renderer/lens_distortion.h"
#include "aar/renderer/projection.h"
#include "aar/renderer/scene_model.h"
#include "aar/rig.h"

namespace aar {
namespace {

using test::SourcePath;

constexpr int kMarginPx = 3;  // the renderer's

Intrinsics TestIntrinsics() {
  Intrinsics k;
  k.width_px = 1024;
  k.height_px = 768;
  k.fx_px = k.fy_px = 1000.0;
  k.cx_px = 511.5;
  k.cy_px = 383.5;
  return k;
}

MeshGeometry OneTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  MeshGeometry mesh;
  mesh.positions = {a, b, c};
  mesh.indices = {0, 1, 2};
  for (const Eigen::Vector3d& p : mesh.positions) mesh.bounds.extend(p);
  return mesh;
}

// A floor 1 m below the camera (OpenCV y down) from 5 m behind it to 100 m
// ahead, narrowing from 2 m to a point: its box reaches behind the camera.
// Its visible part runs from the far vertex's row (v = cy + f / 100,
// framebuffer v + 0.5) down to the image's bottom edge grown by the margin,
// which the floor crosses at z_b = f / (height + margin - 0.5 - cy), where it
// is 2 (100 - z_b) / 105 m wide.
TEST(GeometryRect, TriangleBehindTheCameraGivesItsVisiblePartOnly) {
  const Intrinsics k = TestIntrinsics();
  const Eigen::Matrix4d clip_from_cam = ClipFromCamera(k, 0.5);
  const MeshGeometry floor = OneTriangle({-1.0, 1.0, -5.0}, {1.0, 1.0, -5.0}, {0.0, 1.0, 100.0});
  const PixelRect r = GeometryRect(clip_from_cam, floor, k.width_px, k.height_px, kMarginPx);
  const double far_row = k.cy_px + k.fy_px / 100.0 + 0.5;
  const double z_b = k.fy_px / (k.height_px + kMarginPx - 0.5 - k.cy_px);
  const double half_width_px = k.fx_px * (100.0 - z_b) / 105.0 / z_b;
  EXPECT_NEAR(r.y0, std::floor(far_row) - kMarginPx, 1.0);
  EXPECT_EQ(r.y1, k.height_px);
  EXPECT_NEAR(r.x0, std::floor(k.cx_px + 0.5 - half_width_px) - kMarginPx, 1.0);
  EXPECT_NEAR(r.x1, std::ceil(k.cx_px + 0.5 + half_width_px) + kMarginPx, 1.0);
  EXPECT_LT(r.width(), k.width_px);
  // 50 m above the camera it is above the image (rows < -100) everywhere: nothing to render.
  const MeshGeometry above = OneTriangle({-1.0, -50.0, -5.0}, {1.0, -50.0, -5.0}, {0.0, -50.0, 100.0});
  EXPECT_TRUE(GeometryRect(clip_from_cam, above, k.width_px, k.height_px, kMarginPx).empty());
  // A triangle wholly behind the camera: nothing.
  const MeshGeometry behind = OneTriangle({-1.0, 0.0, -5.0}, {1.0, 0.0, -5.0}, {0.0, 1.0, -1.0});
  EXPECT_TRUE(GeometryRect(clip_from_cam, behind, k.width_px, k.height_px, kMarginPx).empty());
}

// Random triangles around the camera, many crossing its near plane or the
// image's edges: every sampled point of each that lies in front of the near
// plane and inside the image is inside the rectangle.
TEST(GeometryRect, CoversEveryVisiblePointOfRandomTriangles) {
  const Intrinsics k = TestIntrinsics();
  const double near_m = 0.5;
  const Eigen::Matrix4d clip_from_cam = ClipFromCamera(k, near_m, 0.25, -0.25);
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> coordinate(-20.0, 20.0);
  int partial = 0;
  for (int n = 0; n < 400; ++n) {
    const Eigen::Vector3d a(coordinate(rng), coordinate(rng), coordinate(rng));
    const Eigen::Vector3d b(coordinate(rng), coordinate(rng), coordinate(rng));
    const Eigen::Vector3d c(coordinate(rng), coordinate(rng), coordinate(rng));
    const PixelRect r = GeometryRect(clip_from_cam, OneTriangle(a, b, c), k.width_px, k.height_px, kMarginPx);
    bool any_visible = false;
    constexpr int kSteps = 200;
    for (int i = 0; i <= kSteps; ++i) {
      for (int j = 0; i + j <= kSteps; ++j) {
        const Eigen::Vector3d p = a + (b - a) * (double(i) / kSteps) + (c - a) * (double(j) / kSteps);
        if (p.z() < near_m) continue;
        const Eigen::Vector4d clip = clip_from_cam * p.homogeneous();
        const double x = (clip.x() / clip.w() + 1.0) * k.width_px / 2.0;
        const double y = (clip.y() / clip.w() + 1.0) * k.height_px / 2.0;
        if (x < 0.0 || y < 0.0 || x >= k.width_px || y >= k.height_px) continue;
        any_visible = true;
        ASSERT_TRUE(x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1)
            << "triangle " << n << ": (" << x << ", " << y << ") outside [" << r.x0 << ", " << r.x1 << ") x [" << r.y0
            << ", " << r.y1 << ")";
      }
    }
    if (any_visible && std::min({a.z(), b.z(), c.z()}) < 0.0 && (r.width() < k.width_px || r.height() < k.height_px))
      ++partial;
  }
  EXPECT_GT(partial, 10);  // reaching behind the camera no longer means the whole image
}

// The tanker's bounding box contains the cameras of every committed rig (so
// the box alone would give the whole image), yet no part of the tanker comes
// within the margin of either camera's image (rig_clearance_test.cpp shows it
// with 2 deg to spare): its rectangle is empty.
class TankerRect : public ::testing::TestWithParam<const char*> {};

TEST_P(TankerRect, IsEmptyForBothCameras) {
  const StereoRig rig = LoadRig(SourcePath(GetParam()));
  static const MeshGeometry tanker = MeshGeometryOf(LoadSceneModel(SourcePath("scenes/kc46.glb")));
  for (const Camera* camera : {&rig.left, &rig.right}) {
    Intrinsics k = camera->intrinsics;
    if (!k.distortion.IsZero()) {  // rendered as the pinhole stand-in with a margin (lens_distortion.h)
      k = LensResampler(k, LensResampler::RequiredMargin(k, GetParam()), GetParam()).pinhole();
    }
    EXPECT_TRUE(tanker.bounds.contains(camera->tanker_from_camera.translation())) << GetParam();
    const Eigen::Matrix4d clip_from_tanker =
        ClipFromCamera(k, rig.near_m) * camera->tanker_from_camera.inverse().matrix();
    const PixelRect r = GeometryRect(clip_from_tanker, tanker, k.width_px, k.height_px, kMarginPx);
    EXPECT_TRUE(r.empty()) << GetParam() << ": [" << r.x0 << ", " << r.x1 << ") x [" << r.y0 << ", " << r.y1 << ")";
  }
}

INSTANTIATE_TEST_SUITE_P(CommittedRigs, TankerRect, test::kCommittedRigs, test::CommittedRigName);

}  // namespace
}  // namespace aar
