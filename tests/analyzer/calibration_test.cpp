#include "aar/analyzer/calibration.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/pose.h"
#include "aar/rig.h"

namespace aar {
namespace {

constexpr int kSuper = 8;  // samples per pixel side of the synthetic board images (64 per pixel)

StereoRig TestRig() { return LoadRig(std::filesystem::path(AAR_SOURCE_DIR) / "scenes" / "rig.json"); }

/// Pose of a board view, relative to the left camera: the board centre sits at
/// `centre_in_left` and the board is turned by Rx(pitch) Ry(yaw) Rz(roll) from
/// facing the camera squarely (board x = image right, y = image down).
struct BoardView {
  Eigen::Vector3d centre_in_left;
  double pitch_deg, yaw_deg, roll_deg;
};

Eigen::Isometry3d LeftFromBoard(const BoardView& view, const BoardSpec& board) {
  const double rad = M_PI / 180.0;
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(view.pitch_deg * rad, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(view.yaw_deg * rad, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(view.roll_deg * rad, Eigen::Vector3d::UnitZ()))
                                .toRotationMatrix();
  const Eigen::Vector3d centre_in_board(0.5 * board.square_m * (board.inner_corners_x - 1),
                                        0.5 * board.square_m * (board.inner_corners_y - 1), 0.0);
  Eigen::Isometry3d left_from_board = Eigen::Isometry3d::Identity();
  left_from_board.linear() = r;
  left_from_board.translation() = view.centre_in_left - r * centre_in_board;
  return left_from_board;
}

/// 12 views at 14-22 m, tilted 20-30 degrees, inside both images.
std::vector<BoardView> TestViews() {
  return {
      {{0.0, 0.0, 14.0}, 25, 0, 0},    {{0.0, 0.0, 14.5}, -25, 0, 0},   {{0.3, 0.0, 15.0}, 0, 25, 0},
      {{-0.3, 0.0, 15.0}, 0, -25, 0},  {{0.5, 0.3, 17.0}, 20, 20, 5},   {{-0.5, -0.3, 17.0}, -20, -20, -5},
      {{1.0, -0.5, 18.0}, 20, -20, 0}, {{-1.0, 0.5, 18.0}, -20, 20, 0}, {{1.5, -1.0, 20.0}, 30, 10, 0},
      {{-1.5, 1.0, 20.0}, -10, 30, 0}, {{2.0, 1.5, 22.0}, -30, -10, 8}, {{-2.0, -1.5, 22.0}, 10, -30, -8},
  };
}

/// Pixel of a board point (metres, board frame) in a camera; cam_from_board maps board to camera.
cv::Point2d ProjectBoardPoint(const Eigen::Isometry3d& cam_from_board, const Intrinsics& k, double x, double y) {
  const Eigen::Vector3d p = cam_from_board * Eigen::Vector3d(x, y, 0.0);
  return {k.fx_px * p.x() / p.z() + k.cx_px, k.fy_px * p.y() / p.z() + k.cy_px};
}

/// Renders the board (17x18 squares, one square of white border) over a grey
/// background like a multisampled render: kSuper x kSuper point samples per
/// pixel, each mapped to the board plane through the inverse homography and
/// coloured, then averaged (box filter). A pixel whose four corners fall in
/// one board cell lies wholly inside it (cells are convex) and is not sampled.
/// Returns BGR.
cv::Mat RenderBoard(const Eigen::Isometry3d& cam_from_board, const Intrinsics& k, const BoardSpec& board) {
  // image_from_board = K [r1 r2 t] maps board (x, y, 1) to homogeneous pixels.
  Eigen::Matrix3d image_from_board;
  image_from_board << cam_from_board.linear().col(0), cam_from_board.linear().col(1), cam_from_board.translation();
  image_from_board = k.CameraMatrix() * image_from_board;
  const Eigen::Matrix3d h = image_from_board.inverse();
  const double s = board.square_m;
  const int nx = board.inner_corners_x, ny = board.inner_corners_y;
  constexpr int kBackground = 110, kWhite = 235, kBlack = 20, kOutside = -1000000;
  // Cells of side s: squares i in [-1, nx), j in [-1, ny); the border ring is the cells around them.
  auto cell = [&](double u, double v) {
    const double w = h(2, 0) * u + h(2, 1) * v + h(2, 2);
    const double x = (h(0, 0) * u + h(0, 1) * v + h(0, 2)) / w, y = (h(1, 0) * u + h(1, 1) * v + h(1, 2)) / w;
    const int i = static_cast<int>(std::floor(x / s)), j = static_cast<int>(std::floor(y / s));
    if (i < -2 || i > nx || j < -2 || j > ny) return kOutside;
    return (j + 2) * (nx + 3) + (i + 2);
  };
  auto colour = [&](int id) {
    if (id == kOutside) return kBackground;
    const int i = id % (nx + 3) - 2, j = id / (nx + 3) - 2;
    const bool square = i >= -1 && i < nx && j >= -1 && j < ny;
    return square && (i + j + 2) % 2 == 0 ? kBlack : kWhite;
  };
  // Pixels holding an outline corner need sampling even when their corners are all outside.
  std::vector<cv::Point> outline_pixels;
  for (double x : {-2 * s, (nx + 1) * s}) {
    for (double y : {-2 * s, (ny + 1) * s}) {
      const cv::Point2d p = ProjectBoardPoint(cam_from_board, k, x, y);
      outline_pixels.emplace_back(static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)));
    }
  }
  cv::Mat corner_cells(k.height_px + 1, k.width_px + 1, CV_32S);
  for (int v = 0; v <= k.height_px; ++v) {
    for (int u = 0; u <= k.width_px; ++u) corner_cells.at<int>(v, u) = cell(u - 0.5, v - 0.5);
  }
  cv::Mat gray(k.height_px, k.width_px, CV_8U);
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      const int id = corner_cells.at<int>(v, u);
      const bool uniform =
          id == corner_cells.at<int>(v, u + 1) && id == corner_cells.at<int>(v + 1, u) &&
          id == corner_cells.at<int>(v + 1, u + 1) &&
          std::find(outline_pixels.begin(), outline_pixels.end(), cv::Point(u, v)) == outline_pixels.end();
      if (uniform) {
        gray.at<uchar>(v, u) = static_cast<uchar>(colour(id));
        continue;
      }
      int sum = 0;
      for (int sy = 0; sy < kSuper; ++sy) {
        for (int sx = 0; sx < kSuper; ++sx)
          sum += colour(cell(u - 0.5 + (sx + 0.5) / kSuper, v - 0.5 + (sy + 0.5) / kSuper));
      }
      gray.at<uchar>(v, u) = static_cast<uchar>((sum + kSuper * kSuper / 2) / (kSuper * kSuper));
    }
  }
  cv::Mat bgr;
  cv::cvtColor(gray, bgr, cv::COLOR_GRAY2BGR);
  return bgr;
}

/// The board's outer corners lie inside the image with a margin.
bool BoardInside(const Eigen::Isometry3d& cam_from_board, const Intrinsics& k, const BoardSpec& board, double margin) {
  const double s = board.square_m;
  for (double x : {-2 * s, (board.inner_corners_x + 1) * s}) {
    for (double y : {-2 * s, (board.inner_corners_y + 1) * s}) {
      const cv::Point2d p = ProjectBoardPoint(cam_from_board, k, x, y);
      if (p.x < margin || p.y < margin || p.x > k.width_px - 1 - margin || p.y > k.height_px - 1 - margin) return false;
    }
  }
  return true;
}

struct SyntheticSet {
  StereoRig rig;
  std::vector<StereoImagePair> pairs;
  std::vector<Eigen::Isometry3d> left_from_board;
};

/// Rendered once per test binary (about 2 s).
const SyntheticSet& Synthetic() {
  static const SyntheticSet set = [] {
    SyntheticSet s;
    s.rig = TestRig();
    const BoardSpec board;
    const Eigen::Isometry3d right_from_left = s.rig.RightFromLeft();
    size_t i = 0;
    for (const BoardView& view : TestViews()) {
      const Eigen::Isometry3d left_from_board = LeftFromBoard(view, board);
      const Eigen::Isometry3d right_from_board = right_from_left * left_from_board;
      EXPECT_TRUE(BoardInside(left_from_board, s.rig.left.intrinsics, board, 8.0)) << "view " << i;
      EXPECT_TRUE(BoardInside(right_from_board, s.rig.right.intrinsics, board, 8.0)) << "view " << i;
      StereoImagePair pair;
      pair.left_name = "calib/" + FrameStem(i) + "_left.png";
      pair.right_name = "calib/" + FrameStem(i) + "_right.png";
      pair.left = RenderBoard(left_from_board, s.rig.left.intrinsics, board);
      pair.right = RenderBoard(right_from_board, s.rig.right.intrinsics, board);
      s.pairs.push_back(std::move(pair));
      s.left_from_board.push_back(left_from_board);
      ++i;
    }
    return s;
  }();
  return set;
}

/// Calibrated once per test binary.
const CalibrationResult& SyntheticCalibration() {
  static const CalibrationResult result =
      CalibrateFromImages(Synthetic().pairs, CalibrationOptions{}, IdealCalibration(Synthetic().rig));
  return result;
}

TEST(Calibration, CornersAreSubpixelAccurateAndInBoardOrder) {
  const SyntheticSet& set = Synthetic();
  const BoardSpec board;
  const CalibrationOptions options;
  double worst = 0.0, sum = 0.0;
  size_t n = 0;
  for (size_t p = 0; p < set.pairs.size(); ++p) {
    const PairDetection d = DetectBoardPair(set.pairs[p], options);
    ASSERT_TRUE(d.used) << d.reason;
    const Eigen::Isometry3d right_from_board = set.rig.RightFromLeft() * set.left_from_board[p];
    for (int j = 0; j < board.inner_corners_y; ++j) {
      for (int i = 0; i < board.inner_corners_x; ++i) {
        const size_t c = static_cast<size_t>(j) * board.inner_corners_x + i;
        const cv::Point2d truth_l =
            ProjectBoardPoint(set.left_from_board[p], set.rig.left.intrinsics, 0.5 * i, 0.5 * j);
        const cv::Point2d truth_r = ProjectBoardPoint(right_from_board, set.rig.right.intrinsics, 0.5 * i, 0.5 * j);
        const double el = cv::norm(cv::Point2d(d.left_corners[c]) - truth_l);
        const double er = cv::norm(cv::Point2d(d.right_corners[c]) - truth_r);
        worst = std::max({worst, el, er});
        sum += el + er;
        n += 2;
      }
    }
  }
  // Canonical order = board order for these upright views; errors would be metres otherwise.
  EXPECT_LT(worst, 0.25);
  EXPECT_LT(sum / n, 0.1);
}

TEST(Calibration, PairOrderIsConsistentForTurnedImages) {
  // Whatever order findChessboardCorners picks, corner c of the left image and
  // corner c of the right image are the same board corner, the grid is
  // right-handed and the left grid starts at its top-left-most end.
  const BoardSpec board;
  const int nx = board.inner_corners_x, ny = board.inner_corners_y;
  for (const int turn : {cv::ROTATE_180, cv::ROTATE_90_CLOCKWISE, cv::ROTATE_90_COUNTERCLOCKWISE}) {
    for (size_t p : {0u, 5u, 10u}) {
      StereoImagePair pair;
      pair.left_name = Synthetic().pairs[p].left_name;
      pair.right_name = Synthetic().pairs[p].right_name;
      cv::rotate(Synthetic().pairs[p].left, pair.left, turn);  // new buffers: the shared images stay untouched
      cv::rotate(Synthetic().pairs[p].right, pair.right, turn);
      const PairDetection d = DetectBoardPair(pair, CalibrationOptions{});
      ASSERT_TRUE(d.used) << d.reason;
      for (size_t c = 0; c < d.left_corners.size(); ++c) {
        ASSERT_LT(cv::norm(d.right_corners[c] - d.left_corners[c]), 40.0) << "turn " << turn << " pair " << p;
      }
      const cv::Point2f first = d.left_corners.front(), last = d.left_corners.back();
      EXPECT_LE(first.x + first.y, last.x + last.y);
      for (const auto* corners : {&d.left_corners, &d.right_corners}) {
        const cv::Point2f row = (*corners)[nx - 1] - (*corners)[0];
        const cv::Point2f col = (*corners)[static_cast<size_t>(ny - 1) * nx] - (*corners)[0];
        EXPECT_GT(row.x * col.y - row.y * col.x, 0.0f);
      }
    }
  }
}

TEST(Calibration, RecoversFocalLengthAndBaselineFromSyntheticBoards) {
  const CalibrationResult& r = SyntheticCalibration();
  const StereoRig& rig = Synthetic().rig;
  EXPECT_EQ(r.used_pairs, 12u);
  EXPECT_EQ(r.corner_count, 12u * 16 * 17);
  ASSERT_TRUE(r.versus_ideal.has_value());
  const IdealComparison& e = *r.versus_ideal;
  EXPECT_LT(std::abs(e.focal_error_percent), 0.5);
  EXPECT_LT(std::abs(e.left_fx_error_percent), 0.5);
  EXPECT_LT(std::abs(e.right_fx_error_percent), 0.5);
  EXPECT_LT(std::abs(e.baseline_error_percent), 1.0);
  EXPECT_LT(e.left_principal_point_error_px, 1.0);
  EXPECT_LT(e.rotation_error_deg, 0.1);
  EXPECT_LT(e.baseline_direction_error_deg, 0.5);
  EXPECT_LT(e.rectified_principal_point_error_px, 10.0);
  // Q in thesis Table 7's form: four non-zero ideal elements, all close.
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) EXPECT_LT(e.q_percent_error.at<double>(row, col), 1.0) << row << "," << col;
  }
  const StereoCalibration& c = r.calibration;
  EXPECT_NEAR(cv::norm(c.T), rig.Baseline(), 0.01 * rig.Baseline());
  EXPECT_LT(c.T.at<double>(0), 0.0);  // right camera at +x of the left: T = right_from_left translation = (-b, 0, 0)
  EXPECT_EQ(cv::countNonZero(c.D1 != 0), 0);  // fix_distortion default: pinhole model
  // Calibration quality (thesis Table 6 reports 0.12-0.24 px RMS, 0.05-0.15 px epipolar).
  EXPECT_LT(r.rms_reprojection_px, 0.1);
  EXPECT_LT(r.epipolar_error_px, 0.05);
  EXPECT_GT(r.epipolar_error_px, 0.0);
  EXPECT_GE(r.epipolar_algebraic, 0.0);
  std::cout << r.BriefReport();
}

TEST(Calibration, EstimatingDistortionStillRecoversTheRig) {
  CalibrationOptions options;
  options.distortion = DistortionModel::kBrownConradyK3;
  std::vector<PairDetection> detections = SyntheticCalibration().pairs;  // same corners, no re-detection
  const CalibrationResult r =
      CalibrateFromDetections(detections, cv::Size(1024, 768), options, IdealCalibration(Synthetic().rig), "images");
  ASSERT_TRUE(r.versus_ideal.has_value());
  EXPECT_LT(std::abs(r.versus_ideal->focal_error_percent), 1.0);
  EXPECT_LT(std::abs(r.versus_ideal->baseline_error_percent), 1.0);
  EXPECT_LT(r.epipolar_error_px, 0.05);
}

TEST(Calibration, SameFocalLengthGivesBothCamerasOneAndSaysSo) {
  // The synthetic rig's cameras share one focal length; with the constraint
  // stereoCalibrate keeps fx and fy equal across the pair, the baseline's
  // direction stays within the unconstrained fit's bound, and the report
  // names the constraint instead of the one-depth warning.
  CalibrationOptions options;
  options.same_focal_length = true;
  std::vector<PairDetection> detections = SyntheticCalibration().pairs;  // same corners, no re-detection
  const CalibrationResult r =
      CalibrateFromDetections(detections, cv::Size(1024, 768), options, IdealCalibration(Synthetic().rig), "images");
  const StereoCalibration& c = r.calibration;
  EXPECT_EQ(c.M1.at<double>(0, 0), c.M2.at<double>(0, 0));
  EXPECT_EQ(c.M1.at<double>(1, 1), c.M2.at<double>(1, 1));
  EXPECT_NE(SyntheticCalibration().calibration.M1.at<double>(0, 0),
            SyntheticCalibration().calibration.M2.at<double>(0, 0));  // free: they differ
  ASSERT_TRUE(r.versus_ideal.has_value());
  EXPECT_LT(std::abs(r.versus_ideal->focal_error_percent), 0.5);
  EXPECT_LT(r.versus_ideal->baseline_direction_error_deg, 0.5);
  EXPECT_TRUE(r.same_focal_length);
  EXPECT_NE(r.BriefReport().find("one focal length for both cameras"), std::string::npos);
  EXPECT_EQ(r.BriefReport().find("hard to tell apart"), std::string::npos);
}

TEST(Calibration, ReportsTheBoardDepthRangeOfItsViews) {
  const CalibrationResult& r = SyntheticCalibration();
  const BoardSpec board;
  const Eigen::Vector3d centre(0.5 * (board.inner_corners_x - 1) * board.square_m,
                               0.5 * (board.inner_corners_y - 1) * board.square_m, 0.0);
  double nearest = std::numeric_limits<double>::infinity(), farthest = 0.0;
  for (const Eigen::Isometry3d& left_from_board : Synthetic().left_from_board) {
    nearest = std::min(nearest, (left_from_board * centre).z());
    farthest = std::max(farthest, (left_from_board * centre).z());
  }
  ASSERT_LT(nearest, farthest);
  // The views' poses come from calibrateCamera: within a few millimetres per 15 m.
  EXPECT_NEAR(r.board_depth_min_m, nearest, 1e-3 * nearest);
  EXPECT_NEAR(r.board_depth_max_m, farthest, 1e-3 * farthest);
  const bool one_depth = farthest < 1.5 * nearest;
  EXPECT_EQ(r.BriefReport().find("hard to tell apart") != std::string::npos, one_depth) << r.BriefReport();
}

TEST(Calibration, QPercentErrorIsElementwiseAndZeroWhereIdealIsZero) {
  const cv::Mat ideal = (cv::Mat_<double>(4, 4) << 1, 0, 0, -500, 0, 1, 0, -400, 0, 0, 0, 900, 0, 0, 2, 0);
  cv::Mat q = ideal.clone();
  q.at<double>(0, 3) = -505;  // 1 %
  q.at<double>(2, 3) = 891;   // 1 %
  q.at<double>(3, 2) = 2.1;   // 5 %
  q.at<double>(3, 3) = 0.01;  // ideal 0: reported as 0
  const cv::Mat e = QPercentError(q, ideal);
  ASSERT_EQ(e.type(), CV_64F);
  EXPECT_NEAR(e.at<double>(0, 3), 1.0, 1e-12);
  EXPECT_NEAR(e.at<double>(2, 3), 1.0, 1e-12);
  EXPECT_NEAR(e.at<double>(3, 2), 5.0, 1e-12);
  EXPECT_EQ(e.at<double>(3, 3), 0.0);
  EXPECT_EQ(e.at<double>(0, 0), 0.0);
  EXPECT_THROW(QPercentError(cv::Mat::eye(3, 3, CV_64F), ideal), Error);
}

TEST(Calibration, TooFewBoardsIsAnErrorNamingTheCount) {
  const SyntheticSet& set = Synthetic();
  std::vector<StereoImagePair> pairs(set.pairs.begin(), set.pairs.begin() + 6);
  for (size_t i = 2; i < 6; ++i) {
    // A board cut by the image edge: not all 16x17 corners visible.
    pairs[i].left = pairs[i].left.clone();
    pairs[i].left(cv::Rect(0, 0, 1024, 500)).setTo(cv::Scalar(110, 110, 110));
  }
  try {
    CalibrateFromImages(pairs, CalibrationOptions{});
    FAIL() << "expected aar::Error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("only 2 of 6"), std::string::npos) << message;
    EXPECT_NE(message.find("need at least 5"), std::string::npos) << message;
    EXPECT_NE(message.find("calib/000002_left.png: found no 16x17 chessboard"), std::string::npos) << message;
  }
}

/// A minimal dataset folder with `count` calibration pairs from the synthetic set.
// The sidecar of board pair `index`, with the SHA-256 of its images as they are now.
void WriteSidecar(const std::filesystem::path& dir, size_t index) {
  FrameSidecar sidecar;
  sidecar.kind = "calib";
  sidecar.index = index;
  sidecar.rig = Synthetic().rig;
  for (const auto& [role, name] :
       {std::pair{"left", Synthetic().pairs[index].left_name}, {"right", Synthetic().pairs[index].right_name}}) {
    sidecar.files[role] = FileRef{name, Sha256File(dir / name)};
  }
  WriteJsonFile(SidecarPath(dir, "calib", index), SidecarToJson(sidecar));
}

void WriteDataset(const std::filesystem::path& dir, size_t count) {
  std::filesystem::create_directories(dir / kCalibDir);
  nlohmann::json manifest = {
      {"schema", kDatasetSchema}, {"calib", {{"count", count}}}, {"files", nlohmann::json::object()}};
  WriteJsonFile(dir / kManifestName, manifest);
  WriteCalibration(dir / kIdealCalibrationName, IdealCalibration(Synthetic().rig));
  for (size_t i = 0; i < count; ++i) {
    EXPECT_TRUE(cv::imwrite((dir / Synthetic().pairs[i].left_name).string(), Synthetic().pairs[i].left));
    EXPECT_TRUE(cv::imwrite((dir / Synthetic().pairs[i].right_name).string(), Synthetic().pairs[i].right));
    WriteSidecar(dir, i);
  }
}

TEST(Calibration, FromDatasetMatchesInMemoryBitwise) {
  const test::TempDir temp("calibration_dataset");
  const std::filesystem::path& dir = temp.path();
  WriteDataset(dir, Synthetic().pairs.size());
  const CalibrationResult from_disk = CalibrateFromDataset(OpenedDataset::Open(dir), CalibrationOptions{});
  const CalibrationResult& in_memory = SyntheticCalibration();
  ASSERT_TRUE(from_disk.versus_ideal.has_value());
  EXPECT_EQ(from_disk.used_pairs, in_memory.used_pairs);
  EXPECT_EQ(from_disk.rms_reprojection_px, in_memory.rms_reprojection_px);
  for (const auto& [a, b] : {std::pair{&from_disk.calibration.Q, &in_memory.calibration.Q},
                             std::pair{&from_disk.calibration.M1, &in_memory.calibration.M1},
                             std::pair{&from_disk.calibration.T, &in_memory.calibration.T}}) {
    ASSERT_EQ(a->total(), b->total());
    EXPECT_EQ(0, std::memcmp(a->data, b->data, a->total() * a->elemSize()));
  }
  EXPECT_EQ(from_disk.pairs[3].left_name, "calib/000003_left.png");
}

TEST(Calibration, MissingOrCorruptImageIsAnErrorNamingTheFile) {
  const test::TempDir temp("calibration_missing");
  const std::filesystem::path& dir = temp.path();
  WriteDataset(dir, 5);
  std::filesystem::remove(dir / "calib" / "000003_right.png");
  try {
    CalibrateFromDataset(OpenedDataset::Open(dir), CalibrationOptions{});
    FAIL() << "expected aar::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("calib/000003_right.png: missing"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "calib" / "000003_right.png") << "not a png";
  try {
    CalibrateFromDataset(OpenedDataset::Open(dir), CalibrationOptions{});
    FAIL() << "expected aar::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("calib/000003_right.png: SHA-256 differs from the sidecar's"),
              std::string::npos)
        << e.what();
  }
  WriteSidecar(dir, 3);  // a sidecar that vouches for the broken file: the decoder refuses it
  try {
    CalibrateFromDataset(OpenedDataset::Open(dir), CalibrationOptions{});
    FAIL() << "expected aar::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("calib/000003_right.png: not a whole PNG file (no PNG signature)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(CalibrateFromDataset(OpenedDataset::Open(dir / "nope"), CalibrationOptions{}), Error);
}

TEST(Calibration, RejectsInvalidOptions) {
  CalibrationOptions options;
  options.min_pairs = 2;
  try {
    options.Check();
    ADD_FAILURE() << "min_pairs 2 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("min_pairs"), std::string::npos) << e.what();
  }
  options = CalibrationOptions{};
  options.rectify_alpha = 2.0;
  EXPECT_THROW(options.Check(), Error);
  EXPECT_NO_THROW(CalibrationOptions{}.Check());
}

}  // namespace
}  // namespace aar
