// Receiver mesh loading, surface sampling, the shelled model's visibility
// test and PLY files.

#include "aar/analyzer/reference_model.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../test_support.h"
#include "aar/analyzer/mesh.h"
#include "aar/analyzer/ply.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/pose.h"
#include "aar/rig.h"
#include "test_meshes.h"

namespace aar {
namespace {

using test::AddBox;
using test::TempDir;

namespace fs = std::filesystem;

// tanker_from_camera of an OpenCV camera at `eye` looking at `target`, image
// up towards tanker +z.
Eigen::Isometry3d LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d tanker_from_camera = Eigen::Isometry3d::Identity();
  tanker_from_camera.linear().col(0) = x;
  tanker_from_camera.linear().col(1) = y;
  tanker_from_camera.linear().col(2) = z;
  tanker_from_camera.translation() = eye;
  return tanker_from_camera;
}

// Two default-intrinsics cameras 0.5 m apart, 8 m above the tanker origin,
// looking at the receiver 30 m aft; the receiver is at the contact position.
StereoRig TestRig() {
  StereoRig rig;
  const Eigen::Vector3d target(-30.0, 0.0, 0.0);
  rig.left.tanker_from_camera = LookAt({0.0, -0.25, 8.0}, target);
  rig.right.tanker_from_camera = LookAt({0.0, 0.25, 8.0}, target);
  rig.contact_position_m = target;
  return rig;
}

// ---- mesh ----

std::string Base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v =
        (uint32_t(uint8_t(bytes[i])) << 16) | (uint32_t(uint8_t(bytes[i + 1])) << 8) | uint8_t(bytes[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += table[(v >> s) & 63];
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    out += std::string{table[(v >> 18) & 63], table[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const uint32_t v = (uint32_t(uint8_t(bytes[i])) << 16) | (uint32_t(uint8_t(bytes[i + 1])) << 8);
    out += std::string{table[(v >> 18) & 63], table[(v >> 12) & 63], table[(v >> 6) & 63], '='};
  }
  return out;
}

// One triangle (gltf (1,0,0), (0,1,0), (0,0,1)), indexed uint16, in a child
// node scaled by 2 under a root translated by (1,2,3) and turned 90 deg about +Y.
// Returns the glTF JSON and its binary buffer.
std::pair<nlohmann::json, std::string> TriangleGltf() {
  std::string bin(36 + 8, '\0');
  const float positions[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const uint16_t indices[3] = {0, 1, 2};
  std::memcpy(bin.data(), positions, 36);
  std::memcpy(bin.data() + 36, indices, 6);
  const double h = std::sqrt(0.5);
  nlohmann::json j = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes",
       {{{"translation", {1, 2, 3}}, {"rotation", {0, h, 0, h}}, {"children", {1}}},
        {{"scale", {2, 2, 2}}, {"mesh", 0}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"buffers", {{{"byteLength", bin.size()}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
        {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", 3},
         {"type", "VEC3"},
         {"min", {0, 0, 0}},
         {"max", {1, 1, 1}}},
        {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}}},
  };
  return {j, bin};
}

std::string Glb(const nlohmann::json& j, std::string bin) {
  std::string json = j.dump();
  while (json.size() % 4 != 0) json += ' ';
  while (bin.size() % 4 != 0) bin += '\0';
  std::string out;
  const auto u32 = [&out](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  out += "glTF";
  u32(2);
  u32(static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  u32(static_cast<uint32_t>(json.size()));
  u32(0x4E4F534A);
  out += json;
  u32(static_cast<uint32_t>(bin.size()));
  u32(0x004E4942);
  out += bin;
  return out;
}

void ExpectTriangleInBodyFrame(const TriangleMesh& mesh) {
  ASSERT_EQ(mesh.triangles.size(), 1u);
  ASSERT_EQ(mesh.vertices.size(), 3u);
  // gltf v -> scale 2 -> Ry(90): (x, y, z) -> (z, y, -x) -> + (1, 2, 3), then
  // body = (Z, X, Y) of the glTF point.
  const Eigen::Vector3d expected[3] = {{1, 1, 2}, {3, 1, 4}, {3, 3, 2}};
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(mesh.vertices[static_cast<size_t>(i)].isApprox(expected[i], 1e-6))
        << i << ": " << mesh.vertices[static_cast<size_t>(i)].transpose();
  }
  EXPECT_EQ(mesh.triangles[0], Eigen::Vector3i(0, 1, 2));
}

TEST(Mesh, LoadsGlbWithNodeTransformsInBodyFrame) {
  TempDir dir;
  const auto [j, bin] = TriangleGltf();
  WriteFileAtomic(dir.path() / "receiver.glb", Glb(j, bin));
  ExpectTriangleInBodyFrame(LoadReceiverMesh(dir.path() / "receiver.glb"));
}

TEST(Mesh, LoadsGltfWithEmbeddedBuffer) {
  TempDir dir;
  auto [j, bin] = TriangleGltf();
  j["buffers"][0]["uri"] = "data:application/octet-stream;base64," + Base64(bin);
  WriteFileAtomic(dir.path() / "receiver.gltf", j.dump());
  ExpectTriangleInBodyFrame(LoadReceiverMesh(dir.path() / "receiver.gltf"));
}

TEST(Mesh, BadFilesThrowNamingTheFile) {
  TempDir dir;
  const auto expect_error = [](const fs::path& path, const std::string& reason) {
    try {
      LoadReceiverMesh(path);
      ADD_FAILURE() << "no exception for " << path;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path.string()), std::string::npos) << what;
      EXPECT_NE(what.find(reason), std::string::npos) << what;
    }
  };
  expect_error(dir.path() / "missing.glb", "not found");
  WriteFileAtomic(dir.path() / "corrupt.glb", "glTF\x02\0\0\0garbage");
  expect_error(dir.path() / "corrupt.glb", "not a readable glTF file");
  WriteFileAtomic(dir.path() / "corrupt.gltf", "{ this is not json");
  expect_error(dir.path() / "corrupt.gltf", "not a readable glTF file");
  auto [j, bin] = TriangleGltf();
  j["nodes"][1].erase("mesh");
  WriteFileAtomic(dir.path() / "empty.glb", Glb(j, bin));
  expect_error(dir.path() / "empty.glb", "holds no triangles");
}

// ---- sampling ----

TEST(ReferenceModel, SampleSurfaceIsDeterministic) {
  TriangleMesh mesh;
  AddBox(mesh, Eigen::Vector3d::Zero(), {3.0, 1.0, 0.5});
  const auto a = SampleSurface(mesh, 5000, 1);
  const auto b = SampleSurface(mesh, 5000, 1);
  const auto c = SampleSurface(mesh, 5000, 2);
  ASSERT_EQ(a.size(), 5000u);
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(Eigen::Vector3d)));
  EXPECT_NE(0, std::memcmp(a.data(), c.data(), a.size() * sizeof(Eigen::Vector3d)));
  // The generator's raw output is fixed by the C++ standard: pin one sample
  // so that a change of the sampling scheme is noticed.
  const auto one = SampleSurface(mesh, 1, 1);
  EXPECT_EQ(one[0], a[0]);
  EXPECT_EQ(FullModel(mesh).points_in_receiver.size(), 48686u);
  EXPECT_EQ(FullModel(mesh).name, "full");
}

TEST(ReferenceModel, SampleSurfaceIsAreaUniform) {
  // Two triangles in the z = 0 plane with areas 1 and 3.
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {10, 0, 0}, {13, 0, 0}, {10, 2, 0}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  const size_t n = 40000;
  const auto points = SampleSurface(mesh, n, 7);
  size_t small = 0;
  Eigen::Vector3d small_mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) {
    EXPECT_EQ(p.z(), 0.0);
    if (p.x() < 5.0) {
      ++small;
      small_mean += p;
      // Inside the triangle (0,0) (1,0) (0,2): x >= 0, y >= 0, 2x + y <= 2.
      EXPECT_GE(p.x(), 0.0);
      EXPECT_GE(p.y(), 0.0);
      EXPECT_LE(2.0 * p.x() + p.y(), 2.0 + 1e-12);
    }
  }
  // Binomial(n, 1/4): expected 10000, standard deviation about 87.
  EXPECT_NEAR(static_cast<double>(small), n / 4.0, 400.0);
  // Uniform inside the triangle: the mean is the centroid (1/3, 2/3).
  small_mean /= static_cast<double>(small);
  EXPECT_NEAR(small_mean.x(), 1.0 / 3.0, 0.01);
  EXPECT_NEAR(small_mean.y(), 2.0 / 3.0, 0.02);
}

TEST(ReferenceModel, SampleSurfaceRejectsZeroArea) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  mesh.triangles = {{0, 1, 2}};
  EXPECT_THROW(SampleSurface(mesh, 10, 1), Error);
}

// ---- shelled model ----

struct FaceCounts {
  int total[6] = {};
  int kept[6] = {};
  double Fraction(int face) const { return static_cast<double>(kept[face]) / total[face]; }
};

// Faces of the 4 m box at the origin: 0 +x, 1 -x, 2 +y, 3 -y, 4 +z, 5 -z.
int FaceOf(const Eigen::Vector3d& p) {
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(p[axis] - 2.0) < 1e-9) return 2 * axis;
    if (std::abs(p[axis] + 2.0) < 1e-9) return 2 * axis + 1;
  }
  return -1;
}

TEST(ReferenceModel, ShellKeepsFacesTowardTheCameras) {
  TriangleMesh box;
  AddBox(box, Eigen::Vector3d::Zero(), {2.0, 2.0, 2.0});
  const StereoRig rig = TestRig();  // cameras see the +x (front) and +z (top) faces
  const ReferenceModel full = SampleSurfaceWithNormals(box, 30000, 3);
  const ReferenceModel shelled = ShellModel(full, box, rig, ReferenceModelOptions::Loose());
  EXPECT_EQ(shelled.name, "shelled");
  FaceCounts counts;
  for (const Eigen::Vector3d& p : full.points_in_receiver) ++counts.total[FaceOf(p)];
  for (const Eigen::Vector3d& p : shelled.points_in_receiver) ++counts.kept[FaceOf(p)];
  EXPECT_GT(counts.Fraction(0), 0.95) << "front";
  EXPECT_GT(counts.Fraction(4), 0.95) << "top";
  EXPECT_LT(counts.Fraction(1), 0.01) << "back";
  // The bottom and side faces are back-facing; only the strip within a pixel
  // of the silhouette survives the dilated test (the bottom face projects to
  // a band about 36 px tall, so about 1/36 of it).
  EXPECT_LT(counts.Fraction(5), 0.06) << "bottom";
  EXPECT_LT(counts.Fraction(2), 0.3) << "left side";
  EXPECT_LT(counts.Fraction(3), 0.3) << "right side";
}

TEST(ReferenceModel, ShellUsesEitherCameraUnlessBothAreRequired) {
  TriangleMesh box;
  AddBox(box, Eigen::Vector3d::Zero(), {2.0, 2.0, 2.0});
  StereoRig rig = TestRig();
  rig.right.tanker_from_camera = LookAt({0.0, 0.25, 8.0}, {30.0, 0.0, 8.0});  // looking forward, away
  const ReferenceModel full = SampleSurfaceWithNormals(box, 5000, 4);
  ReferenceModelOptions options = ReferenceModelOptions::Loose();
  const ReferenceModel either = ShellModel(full, box, rig, options);
  EXPECT_GT(either.points_in_receiver.size(), full.points_in_receiver.size() / 5);
  options.cameras = ShellCameras::kLeft;
  EXPECT_EQ(ShellModel(full, box, rig, options).points_in_receiver.size(), either.points_in_receiver.size());
  options.cameras = ShellCameras::kBoth;
  EXPECT_TRUE(ShellModel(full, box, rig, options).points_in_receiver.empty());
}

TEST(ReferenceModel, StrictShellHasNoBackFacingOrGrazingPoint) {
  TriangleMesh box;
  AddBox(box, Eigen::Vector3d::Zero(), {2.0, 2.0, 2.0});
  const StereoRig rig = TestRig();  // front face seen at ~75 deg, top at ~15 deg, sides edge-on
  const ReferenceModel full = SampleSurfaceWithNormals(box, 30000, 3);
  const ReferenceModelOptions options;  // strict default: both cameras, >= 15 deg
  const ReferenceModel shelled = ShellModel(full, box, rig, options);
  ASSERT_EQ(shelled.normals_in_receiver.size(), shelled.points_in_receiver.size());
  const Eigen::Isometry3d tanker_from_receiver = ShellTankerFromReceiver(rig, options);
  const double min_sine = std::sin(15.0 * M_PI / 180.0);
  FaceCounts counts;
  for (const Eigen::Vector3d& p : full.points_in_receiver) ++counts.total[FaceOf(p)];
  for (size_t i = 0; i < shelled.points_in_receiver.size(); ++i) {
    const Eigen::Vector3d p = tanker_from_receiver * shelled.points_in_receiver[i];
    const Eigen::Vector3d n = tanker_from_receiver.linear() * shelled.normals_in_receiver[i];
    for (const Camera* camera : {&rig.left, &rig.right}) {
      const Eigen::Vector3d ray = (p - camera->tanker_from_camera.translation()).normalized();
      EXPECT_GE(-n.dot(ray), min_sine) << "point " << i << " is back-facing or grazing";
    }
    ++counts.kept[FaceOf(shelled.points_in_receiver[i])];
  }
  EXPECT_GT(counts.Fraction(0), 0.99) << "front";
  for (int face : {1, 2, 3, 5}) EXPECT_EQ(counts.kept[face], 0) << "face " << face;
}

TEST(ReferenceModel, OccluderHidesPointsBehindIt) {
  TriangleMesh scene;
  AddBox(scene, Eigen::Vector3d::Zero(), {2.0, 2.0, 2.0});
  const StereoRig rig = TestRig();
  const std::vector<Eigen::Vector3d> points = SampleSurface(scene, 2000, 5);
  const Eigen::Isometry3d left_from_receiver =
      rig.left.tanker_from_camera.inverse() * ShellTankerFromReceiver(rig, ReferenceModelOptions{});
  const auto visible = VisibleInCamera(points, {}, scene, rig.left.intrinsics, left_from_receiver, rig.near_m);
  size_t seen = 0;
  for (const bool v : visible) seen += v ? 1 : 0;
  EXPECT_GT(seen, 0u);
  // A large wall between the camera and the box (in receiver coordinates, 10 m
  // in front of it) hides everything.
  AddBox(scene, {10.0, 0.0, 0.0}, {0.1, 20.0, 20.0});
  for (const bool v : VisibleInCamera(points, {}, scene, rig.left.intrinsics, left_from_receiver, rig.near_m)) {
    EXPECT_FALSE(v);
  }
}

TEST(ReferenceModel, PointsOutsideTheImageOrBehindAreNotVisible) {
  TriangleMesh nothing;  // an empty z-buffer: only the frustum matters
  const Intrinsics k;    // 1024 x 768, f = 900
  const std::vector<Eigen::Vector3d> points = {{0, 0, 10}, {0, 0, -10}, {100, 0, 10}, {0, 0, 0.1}};
  const auto visible = VisibleInCamera(points, {}, nothing, k, Eigen::Isometry3d::Identity(), 0.5);
  EXPECT_EQ(visible, (std::vector<bool>{true, false, false, false}));
}

// ---- PLY ----

TEST(ReferenceModel, PlyRoundTrip) {
  TempDir dir;
  const std::vector<Eigen::Vector3d> points = {{1.5, -2.25, 3.0}, {-47.712812921, 0.1, -18.9}, {0, 0, 0}};
  const fs::path path = dir.path() / "model.ply";
  WritePly(path, points, {"frame receiver"});
  const std::string bytes = ReadFileBytes(path);
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment frame receiver\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\nend_header\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  EXPECT_EQ(bytes.size(), header.size() + 3 * 12);
  const std::vector<Eigen::Vector3d> read = ReadPly(path);
  ASSERT_EQ(read.size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) EXPECT_EQ(read[i], points[i].cast<float>().cast<double>());
  for (const auto& entry : fs::directory_iterator(dir.path())) EXPECT_EQ(entry.path().filename(), "model.ply");
}

TEST(ReferenceModel, ReadsAsciiPlyWithExtraPropertiesAndElements) {
  TempDir dir;
  const fs::path path = dir.path() / "ascii.ply";
  WriteFileAtomic(path,
                  "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nelement vertex 2\r\nproperty double x\r\n"
                  "property uchar red\r\nproperty double y\r\nproperty double z\r\nelement face 1\r\n"
                  "property list uchar int vertex_indices\r\nend_header\r\n1.25 255 -2 3e1\r\n4 0 5 6\r\n3 0 1 1\r\n");
  const std::vector<Eigen::Vector3d> read = ReadPly(path);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0], Eigen::Vector3d(1.25, -2.0, 30.0));
  EXPECT_EQ(read[1], Eigen::Vector3d(4.0, 5.0, 6.0));
}

TEST(ReferenceModel, ReadPlyRejectsBadFilesWithReasons) {
  TempDir dir;
  const auto expect_error = [&dir](const std::string& name, const std::string& content, const std::string& reason) {
    const fs::path path = dir.path() / name;
    if (!content.empty()) WriteFileAtomic(path, content);
    try {
      ReadPly(path);
      ADD_FAILURE() << "no exception for " << name;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path.string()), std::string::npos) << what;
      EXPECT_NE(what.find(reason), std::string::npos) << what;
    }
  };
  expect_error("missing.ply", "", "missing.ply");
  expect_error("not.ply", "solid cube\n", "not a PLY file");
  expect_error("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 1\n", "no end_header");
  expect_error("no_z.ply",
               "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n",
               "lacks x, y or z");
  std::string truncated =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header\n";
  truncated += std::string(12, '\0');
  expect_error("truncated.ply", truncated, "truncated");
  expect_error("bad_value.ply",
               "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
               "property float z\nend_header\n1 two 3\n",
               "malformed value");
  // A header announcing 10^15 vertices is refused before any memory is reserved for them.
  for (const char* format : {"ascii", "binary_little_endian"}) {
    expect_error(std::string("huge_") + format + ".ply",
                 std::string("ply\nformat ") + format +
                     " 1.0\nelement vertex 1000000000000000\nproperty float x\nproperty float y\n"
                     "property float z\nend_header\n1 2 3\n",
                 "element 'vertex' announces 1000000000000000 items");
  }
  // A skipped element whose size overflows size_t.
  expect_error("overflow.ply",
               "ply\nformat binary_little_endian 1.0\nelement face 4611686018427387904\nproperty int a\n"
               "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
               "element 'face' announces");
}

}  // namespace
}  // namespace aar
