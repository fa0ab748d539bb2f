// `aar-analyze export` on the near-contact dataset (depth truth of both
// cameras): BOP poses project the model onto the exported masks, Middlebury
// disparity is f b / Z and consistent between the views, TUM and ROS files
// carry the truth, the estimates and the calibration, and so does the ROS bag as
// python3-rosbag reads it; bad input writes nothing.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "aar/analyzer/analysis_run.h"
#include "aar/analyzer/frame_results.h"
#include "aar/analyzer/ply.h"
#include "aar/dataset.h"
#include "aar/file_io.h"
#include "aar/text.h"
#include "pipeline_support.h"

namespace aar {
namespace {

namespace fs = std::filesystem;
using test::Quote;
using test::RunAnalyze;
using test::SharedDatasets;
using test::TempDir;

::testing::AssertionResult Export(const fs::path& dataset, const std::string& format, const fs::path& out,
                                  const std::string& flags = "") {
  const test::CommandResult r =
      RunAnalyze("export " + Quote(dataset) + " --format " + format + " --out " + Quote(out) + " " + flags);
  if (r.exit_code == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "aar-analyze export exit code " << r.exit_code << ": " << r.output;
}

Eigen::Matrix3d Matrix3(const nlohmann::json& row_major) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = row_major.at(static_cast<size_t>(i)).get<double>();
  return m;
}

// Reads a PFM written little-endian, bottom row first; returns row 0 = top.
cv::Mat ReadPfm(const fs::path& path) {
  std::istringstream in(ReadFileBytes(path));
  std::string magic;
  int width = 0, height = 0;
  double scale = 0.0;
  in >> magic >> width >> height >> scale;
  in.get();  // the single whitespace after the scale
  EXPECT_EQ(magic, "Pf") << path;
  EXPECT_LT(scale, 0.0) << path << ": not little-endian";
  cv::Mat image(height, width, CV_32FC1);
  for (int y = height - 1; y >= 0; --y) in.read(reinterpret_cast<char*>(image.ptr<float>(y)), width * 4);
  EXPECT_TRUE(in) << path << ": short";
  return image;
}

std::map<std::string, std::string> ReadCalibTxt(const fs::path& path) {
  std::map<std::string, std::string> values;
  std::istringstream in(ReadFileBytes(path));
  for (std::string line; std::getline(in, line);) {
    const size_t eq = line.find('=');
    if (eq != std::string::npos) values[line.substr(0, eq)] = line.substr(eq + 1);
  }
  return values;
}

TEST(Export, BopPosesProjectTheModelOntoTheMasks) {
  ASSERT_DATASETS();
  TempDir dir("export-bop");
  const fs::path out = dir / "bop";
  ASSERT_TRUE(Export(SharedDatasets().near_contact, "bop", out, "--frames 0:2"));
  const std::vector<Eigen::Vector3d> model_mm = ReadPly(out / "models/obj_000001.ply");
  ASSERT_GT(model_mm.size(), 1000u);
  const nlohmann::json info = ReadJsonFile(out / "models/models_info.json").at("1");
  EXPECT_GT(info.at("diameter").get<double>(), 10000.0);  // a C-12: over 10 m [mm]
  for (const char* side : {"left", "right"}) {
    const fs::path scene = out / (std::string("test_") + side) / "000001";
    const nlohmann::json cameras = ReadJsonFile(scene / "scene_camera.json");
    const nlohmann::json gt = ReadJsonFile(scene / "scene_gt.json");
    const nlohmann::json gt_info = ReadJsonFile(scene / "scene_gt_info.json");
    ASSERT_EQ(gt.size(), 2u) << side;
    for (const char* id : {"0", "1"}) {
      const std::string stem = FrameStem(std::stoul(id));
      const double depth_scale = cameras.at(id).at("depth_scale").get<double>();
      EXPECT_GE(depth_scale * 65535.0, 175000.0);  // covers region A
      const Eigen::Matrix3d k = Matrix3(cameras.at(id).at("cam_K"));
      const nlohmann::json& pose = gt.at(id).at(0);
      EXPECT_EQ(pose.at("obj_id").get<int>(), 1);
      const Eigen::Matrix3d r = Matrix3(pose.at("cam_R_m2c"));
      const Eigen::Vector3d t(pose.at("cam_t_m2c").at(0).get<double>(), pose.at("cam_t_m2c").at(1).get<double>(),
                              pose.at("cam_t_m2c").at(2).get<double>());
      const cv::Mat mask = cv::imread((scene / "mask" / (stem + "_000000.png")).string(), cv::IMREAD_UNCHANGED);
      const cv::Mat visib = cv::imread((scene / "mask_visib" / (stem + "_000000.png")).string(), cv::IMREAD_UNCHANGED);
      const cv::Mat depth = cv::imread((scene / "depth" / (stem + ".png")).string(), cv::IMREAD_UNCHANGED);
      ASSERT_EQ(mask.type(), CV_8UC1);
      ASSERT_EQ(depth.type(), CV_16UC1);
      cv::Mat near_mask;  // the mask grown by one pixel: silhouette edges are rasterized at pixel centres
      cv::dilate(mask, near_mask, cv::Mat::ones(3, 3, CV_8U));
      size_t inside = 0, on_mask = 0, near = 0, on_surface = 0, in_front = 0;
      for (const Eigen::Vector3d& x : model_mm) {
        const Eigen::Vector3d p = r * x + t;
        const Eigen::Vector3d uv = k * p / p.z();
        const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
        if (u < 0 || v < 0 || u >= mask.cols || v >= mask.rows) continue;
        ++inside;
        if (mask.at<uint8_t>(v, u) == 255) ++on_mask;
        if (near_mask.at<uint8_t>(v, u) == 255) ++near;
        // Against the depth image: a vertex is on the surface seen there or behind it (hidden), up to the
        // depth change across the pixel it is rounded to (100 mm; edges of near parts over far ones excepted).
        if (visib.at<uint8_t>(v, u) != 255) continue;
        const double seen_mm = depth.at<uint16_t>(v, u) * depth_scale;
        if (std::abs(seen_mm - p.z()) < 100.0) ++on_surface;
        if (seen_mm - p.z() > 100.0) ++in_front;
      }
      const double fraction = static_cast<double>(on_mask) / static_cast<double>(inside);
      const double front_fraction = static_cast<double>(in_front) / static_cast<double>(inside);
      std::printf(
          "%s frame %s: %zu of %zu model vertices on the mask (%.4f), %zu within 1 px; %zu on the depth "
          "surface (100 mm), %zu in front of it (%.4f)\n",
          side, id, on_mask, inside, fraction, near, on_surface, in_front, front_fraction);
      EXPECT_GT(inside, model_mm.size() * 9 / 10) << side << " " << id;
      // Vertices lie on silhouette edges and thin parts, which pixel centres miss: measured 0.933, all within 1 px.
      EXPECT_GT(fraction, 0.9) << side << " " << id;
      EXPECT_EQ(near, inside) << side << " " << id;
      EXPECT_GT(on_surface, inside / 4) << side << " " << id;  // measured 0.44
      EXPECT_LT(front_fraction, 0.02) << side << " " << id;    // measured 0.010-0.012
      // Visible part inside the silhouette; the counts are the masks'.
      EXPECT_EQ(cv::countNonZero(visib & ~mask), 0) << side << " " << id;
      const nlohmann::json& stats = gt_info.at(id).at(0);
      EXPECT_EQ(stats.at("px_count_all").get<int>(), cv::countNonZero(mask));
      EXPECT_EQ(stats.at("px_count_visib").get<int>(), cv::countNonZero(visib));
      EXPECT_GT(stats.at("visib_fract").get<double>(), 0.5);
      EXPECT_LE(stats.at("visib_fract").get<double>(), 1.0);
    }
  }
}

TEST(Export, MiddleburyDisparityIsFocalTimesBaselineOverDepth) {
  ASSERT_DATASETS();
  TempDir dir("export-middlebury");
  const fs::path out = dir / "mb";
  const fs::path dataset = SharedDatasets().near_contact;
  ASSERT_TRUE(Export(dataset, "middlebury", out, "--frames 3:4"));
  const FrameSidecar sidecar = ReadSidecar(SidecarPath(dataset, "frame", 3));
  const std::map<std::string, std::string> calib = ReadCalibTxt(out / "000003/calib.txt");
  const double f = sidecar.rig.left.intrinsics.fx_px;
  const double baseline_mm = std::stod(calib.at("baseline"));
  EXPECT_NEAR(baseline_mm, sidecar.rig.Baseline() * 1000.0, 1e-6);
  EXPECT_EQ(calib.at("doffs"), "0");
  EXPECT_EQ(calib.at("width"), "1024");
  EXPECT_EQ(ReadFileBytes(out / "000003/im0.png"), ReadFileBytes(dataset / sidecar.files.at("left").path));

  const cv::Mat d0 = ReadPfm(out / "000003/disp0GT.pfm"), d1 = ReadPfm(out / "000003/disp1GT.pfm");
  const cv::Mat z0 = cv::imread((dataset / sidecar.files.at("left_depth").path).string(), cv::IMREAD_UNCHANGED);
  const cv::Mat ids0 = cv::imread((dataset / sidecar.files.at("left_mask").path).string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(z0.type(), CV_32FC1);
  ASSERT_EQ(d0.size(), z0.size());
  double max_relative = 0.0, max_d = 0.0;
  size_t receiver = 0, consistent = 0;
  for (int v = 0; v < z0.rows; ++v) {
    for (int u = 0; u < z0.cols; ++u) {
      const float z = z0.at<float>(v, u), d = d0.at<float>(v, u);
      if (!(z > 0.0f)) {
        ASSERT_TRUE(std::isinf(d)) << u << "," << v;
        continue;
      }
      const double expected = f * baseline_mm / 1000.0 / z;
      max_relative = std::max(max_relative, std::abs(d - expected) / expected);
      max_d = std::max(max_d, static_cast<double>(d));
      // Left-right consistency on the receiver: the right view at u - d sees the same point.
      if (ids0.at<uint8_t>(v, u) != 1) continue;
      ++receiver;
      const int ur = static_cast<int>(std::lround(u - d));
      if (ur >= 0 && std::abs(d1.at<float>(v, ur) - d) < 0.05f) ++consistent;
    }
  }
  const double consistent_fraction = static_cast<double>(consistent) / static_cast<double>(receiver);
  std::printf("disparity vs f b / Z: max relative error %.2e; %zu receiver pixels, %.4f consistent within 0.05 px\n",
              max_relative, receiver, consistent_fraction);
  EXPECT_LT(max_relative, 1e-6);
  EXPECT_GT(receiver, 10000u);
  EXPECT_GT(consistent_fraction, 0.95);
  EXPECT_GE(std::stoi(calib.at("ndisp")), static_cast<int>(std::ceil(max_d)));
}

TEST(Export, TumRosAndRosbagCarryTruthEstimatesAndCalibration) {
  ASSERT_DATASETS();
  TempDir dir("export-tum");
  const fs::path dataset = SharedDatasets().near_contact;
  const test::CommandResult run = RunAnalyze("run " + Quote(dataset) + " --no-progress --frames 0:2 --calibration " +
                                             Quote(dataset / kIdealCalibrationName) + " --out " + Quote(dir / "run"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_TRUE(Export(dataset, "tum", dir / "tum", "--frames 0:2 --run " + Quote(dir / "run")));
  for (const char* name : {"truth.tum", "estimate.tum"}) {
    std::istringstream in(ReadFileBytes(dir / "tum" / name));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line[0], '#') << name;
    for (size_t index = 0; index < 2; ++index) {
      ASSERT_TRUE(std::getline(in, line)) << name;
      std::istringstream fields(line);
      double t, x, y, z, qx, qy, qz, qw;
      ASSERT_TRUE(fields >> t >> x >> y >> z >> qx >> qy >> qz >> qw) << line;
      const FrameSidecar s = ReadSidecar(SidecarPath(dataset, "frame", index));
      const Eigen::Isometry3d truth = IsometryFromPose(s.tanker_from_target);
      const double tolerance_m = std::string(name) == "truth.tum" ? 1e-8 : 0.3;
      EXPECT_NEAR(t, s.time_s, 1e-9) << name;
      EXPECT_LT((Eigen::Vector3d(x, y, z) - truth.translation()).norm(), tolerance_m) << name << ": " << line;
      const Eigen::Quaterniond q(qw, qx, qy, qz);
      EXPECT_NEAR(q.norm(), 1.0, 1e-8) << line;
      EXPECT_LT(q.angularDistance(Eigen::Quaterniond(truth.linear())), std::string(name) == "truth.tum" ? 1e-8 : 0.02)
          << name << ": " << line;
    }
    EXPECT_FALSE(std::getline(in, line)) << name << ": more than two frames";
  }

  ASSERT_TRUE(Export(dataset, "ros", dir / "ros"));
  const FrameSidecar s = ReadSidecar(SidecarPath(dataset, "frame", 0));
  const Intrinsics& k = s.rig.left.intrinsics;
  const std::string fb = std::to_string(-k.fx_px * s.rig.Baseline());
  const std::string right = ReadFileBytes(dir / "ros/right.yaml");
  EXPECT_NE(ReadFileBytes(dir / "ros/left.yaml").find("camera_name: left\n"), std::string::npos);
  EXPECT_NE(right.find("distortion_model: plumb_bob\n"), std::string::npos) << right;
  // projection_matrix data: [f, 0, cx, -f b, ...]: compare the Tx entry numerically.
  const size_t p = right.find("projection_matrix:");
  ASSERT_NE(p, std::string::npos) << right;
  const size_t data = right.find("data: [", p) + 7;
  std::istringstream entries(right.substr(data));
  std::vector<double> values;
  for (std::string entry; std::getline(entries, entry, ',') && values.size() < 4;) values.push_back(std::stod(entry));
  ASSERT_EQ(values.size(), 4u);
  EXPECT_DOUBLE_EQ(values[0], k.fx_px);
  EXPECT_DOUBLE_EQ(values[2], k.cx_px);
  EXPECT_NEAR(values[3], -k.fx_px * s.rig.Baseline(), 1e-9) << fb;

  // The bag, read back by Debian's python3-rosbag (tests/pipeline/check_rosbag.py).
  ASSERT_TRUE(Export(dataset, "rosbag", dir / "bag", "--frames 0:2 --run " + Quote(dir / "run")));
  const test::CommandResult check =
      test::RunCommand("/usr/bin/python3 " + Quote(test::SourcePath("tests/pipeline/check_rosbag.py")) + " " +
                       Quote(dir / "bag/dataset.bag") + " " + Quote(dataset) + " 0 2 " + Quote(dir / "run"));
  EXPECT_EQ(check.exit_code, 0) << check.output;
  EXPECT_NE(check.output.find("rosbag ok: 15 messages on 8 topics, 2 estimates"), std::string::npos) << check.output;
}

TEST(Export, WithoutDepthTruthFailsNamingTheSidecarAndWritesNothing) {
  ASSERT_DATASETS();
  TempDir dir("export-bad");
  for (const char* format : {"bop", "middlebury"}) {
    const fs::path out = dir / format;
    const test::CommandResult r =
        RunAnalyze("export " + Quote(SharedDatasets().out_of_view) + " --format " + format + " --out " + Quote(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(test::CountLines(r.output), 1u) << r.output;
    EXPECT_NE(r.output.find("frames/000000.json: no left_depth (render with --depth)"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out)) << out;
  }
  const test::CommandResult r =
      RunAnalyze("export " + Quote(SharedDatasets().out_of_view) + " --format xyz --out " + Quote(dir / "x"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--format 'xyz': expected bop, middlebury, tum, ros or rosbag"), std::string::npos)
      << r.output;
}

TEST(Export, ChangedSidecarFailsNamingItAndWritesNothing) {
  ASSERT_DATASETS();
  TempDir dir("export-changed");
  const fs::path dataset = dir / "ds";
  test::CopyDataset(SharedDatasets().out_of_view, dataset);
  WriteFileAtomic(SidecarPath(dataset, "frame", 1), ReadFileBytes(SidecarPath(dataset, "frame", 1)) + " ");
  const fs::path out = dir / "tum";
  const test::CommandResult r = RunAnalyze("export " + Quote(dataset) + " --format tum --out " + Quote(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(test::CountLines(r.output), 1u) << r.output;
  EXPECT_NE(r.output.find("frames/000001.json: SHA-256 differs from manifest.json's"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out)) << out;
}

// `run --dump-frames`: the overlay's model points and the disparity lie on the
// receiver (the dataset's silhouette truth), the PLYs hold the run's clouds.
TEST(FrameDump, OverlayAndDisparityLieOnTheReceiver) {
  ASSERT_DATASETS();
  TempDir dir("frame-dump");
  const fs::path dataset = SharedDatasets().near_contact;
  const fs::path out = dir / "run";
  const test::CommandResult run =
      RunAnalyze("run " + Quote(dataset) + " --no-progress --frames 2:3 --calibration " +
                 Quote(dataset / kIdealCalibrationName) + " --dump-frames 2 --out " + Quote(out));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<FrameResult> frames = ReadFrameResults(out / kFramesCsvName);
  ASSERT_EQ(frames.size(), 1u);
  ASSERT_TRUE(frames[0].ok()) << frames[0].status;
  const FrameSidecar s = ReadSidecar(SidecarPath(dataset, "frame", 2));
  const cv::Mat left = cv::imread((dataset / s.files.at("left").path).string(), cv::IMREAD_COLOR);
  const cv::Mat silhouette = cv::imread((dataset / s.files.at("left_silhouette").path).string(), cv::IMREAD_UNCHANGED);
  cv::Mat near_receiver;  // the silhouette grown by 2 px (estimate error, block-matching edges)
  cv::dilate(silhouette, near_receiver, cv::Mat::ones(5, 5, CV_8U));

  const cv::Mat overlay = cv::imread((out / "frames/000002_overlay.png").string(), cv::IMREAD_COLOR);
  ASSERT_EQ(overlay.size(), left.size());
  size_t drawn = 0, drawn_on_receiver = 0;
  for (int v = 0; v < overlay.rows; ++v) {
    for (int u = 0; u < overlay.cols; ++u) {
      if (overlay.at<cv::Vec3b>(v, u) != cv::Vec3b(0, 255, 0) || left.at<cv::Vec3b>(v, u) == cv::Vec3b(0, 255, 0))
        continue;
      ++drawn;
      if (near_receiver.at<uint8_t>(v, u) == 255) ++drawn_on_receiver;
    }
  }
  const cv::Mat disparity = cv::imread((out / "frames/000002_disparity.png").string(), cv::IMREAD_COLOR);
  ASSERT_EQ(disparity.size(), left.size());
  cv::Mat coloured;
  cv::cvtColor(disparity, coloured, cv::COLOR_BGR2GRAY);
  coloured = coloured > 0;
  const int with_disparity = cv::countNonZero(coloured);
  const int disparity_on_receiver = cv::countNonZero(coloured & near_receiver);
  std::printf("overlay: %zu green pixels, %.4f on the receiver; disparity: %d pixels, %.4f on the receiver\n", drawn,
              static_cast<double>(drawn_on_receiver) / drawn, with_disparity,
              static_cast<double>(disparity_on_receiver) / with_disparity);
  EXPECT_GT(drawn, 2000u);
  EXPECT_GT(static_cast<double>(drawn_on_receiver) / drawn, 0.97);
  EXPECT_GT(with_disparity, 10000);
  EXPECT_GT(static_cast<double>(disparity_on_receiver) / with_disparity, 0.97);

  EXPECT_EQ(ReadPly(out / "frames/000002_sensed.ply").size(), frames[0].sensed_points);
  const std::vector<Eigen::Vector3d> model = ReadPly(out / "frames/000002_model.ply");
  EXPECT_EQ(model.size(), ReadPly(out / "reference_shelled.ply").size());
  // The model PLY is the reference at the estimate: its origin's image is the estimated translation.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero(), reference_centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : model) centroid += p / static_cast<double>(model.size());
  for (const Eigen::Vector3d& p : ReadPly(out / "reference_shelled.ply")) reference_centroid += p;
  reference_centroid /= static_cast<double>(model.size());
  const Eigen::Vector3d expected = IsometryFromPose(frames[0].estimate) * reference_centroid;
  EXPECT_LT((centroid - expected).norm(), 1e-3);  // float PLY, 6-decimal CSV

  // points.csv: one line per sensed point; its errors against the true
  // disparities are the frame's depth-truth sums in frames.csv.
  std::istringstream points(ReadFileBytes(out / "frames/000002_points.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(points, line));
  EXPECT_EQ(line, "u_px,v_px,disparity_px,true_disparity_px");
  size_t rows = 0, on_receiver = 0;
  double error_sum = 0.0;
  while (std::getline(points, line)) {
    ++rows;
    const std::vector<std::string> fields = SplitCsvLine(line);
    ASSERT_EQ(fields.size(), 4u) << line;
    if (fields[3].empty()) continue;
    ++on_receiver;
    error_sum += std::stod(fields[2]) - std::stod(fields[3]);
  }
  EXPECT_EQ(rows, frames[0].sensed_points);
  EXPECT_EQ(on_receiver, frames[0].stereo_truth.on_receiver);
  EXPECT_NEAR(error_sum, frames[0].stereo_truth.error_sum_px, 1e-3);

  // experiments/edge_bias.py reads the dump: the same points and mean error.
  const test::CommandResult edge =
      test::RunCommand("/usr/bin/python3 " + Quote(test::SourcePath("experiments/edge_bias.py")) + " " + Quote(out));
  ASSERT_EQ(edge.exit_code, 0) << edge.output;
  const std::string row_start = "| " + out.string() + " | " + std::to_string(on_receiver) + " | ";
  const size_t row = edge.output.find(row_start);
  ASSERT_NE(row, std::string::npos) << row_start << " in\n" << edge.output;
  EXPECT_NEAR(std::stod(edge.output.substr(row + row_start.size())), error_sum / static_cast<double>(on_receiver),
              1e-4);
}

}  // namespace
}  // namespace aar
