// Rolling shutter (rolling_shutter.h, docs/rendering.md "Rolling shutter"):
// the bands' instants and rows, the band of a pinhole pixel through a lens,
// and the render job's frames against the receiver's motion.

#include "aar/renderer/rolling_shutter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/file_io.h"
#include "aar/lens.h"
#include "aar/renderer/lens_distortion.h"
#include "aar/renderer/stereo_render_job.h"
#include "aar/rig.h"

namespace aar {
namespace {

using test::SourcePath;
using test::TempDir;

TEST(RollingShutter, BandsAreEqualSlicesOfTheReadoutAboutTheSample) {
  const std::vector<double> three = ReadoutBandOffsets(30.0, 3);
  ASSERT_EQ(three.size(), 3u);
  EXPECT_NEAR(three[0], -10e-3, 1e-15);
  EXPECT_EQ(three[1], 0.0);
  EXPECT_NEAR(three[2], 10e-3, 1e-15);
  // Every row's band instant is within readout / (2 bands) of the row's own.
  const int height = 768, bands = 32;
  const double readout_ms = 30.0;
  const std::vector<double> offsets = ReadoutBandOffsets(readout_ms, bands);
  for (int r = 0; r < height; ++r) {
    const double row_s = 1e-3 * readout_ms * ((r + 0.5) / height - 0.5);
    EXPECT_LE(std::abs(offsets[ReadoutBand(r, height, bands)] - row_s), 1e-3 * readout_ms / (2 * bands) + 1e-12)
        << "row " << r;
  }
  EXPECT_EQ(ReadoutBand(-3.0, height, bands), 0);  // beyond the frame: the nearest band
  EXPECT_EQ(ReadoutBand(900.0, height, bands), bands - 1);
}

TEST(RollingShutter, APinholeCamerasBandsAreItsRows) {
  const Intrinsics k = LoadRig(SourcePath("scenes/rig.json")).left.intrinsics;
  const ReadoutBands bands(k, k, 32);
  for (int b = 0; b < 32; ++b) {
    const PixelRect& rows = bands.Rows(b);
    EXPECT_EQ(rows.x0, 0);
    EXPECT_EQ(rows.x1, k.width_px);
    EXPECT_EQ(rows.y0, 24 * b);
    EXPECT_EQ(rows.y1, 24 * b + 24);
  }
  // Composite takes band b's pixels and nothing else.
  LinearImage frame{k.width_px, k.height_px, std::vector<float>(static_cast<size_t>(k.width_px) * k.height_px * 3)};
  LinearImage band = frame;
  std::fill(band.rgb.begin(), band.rgb.end(), 1.0f);
  bands.Composite(5, band, frame);
  for (int y = 0; y < k.height_px; ++y) {
    const float expected = y >= 120 && y < 144 ? 1.0f : 0.0f;
    EXPECT_EQ(frame.rgb[(static_cast<size_t>(y) * k.width_px + 7) * 3 + 1], expected) << "row " << y;
  }
  EXPECT_THROW(ReadoutBands(k, k, 0), Error);
  EXPECT_THROW(ReadoutBands(k, k, kMaxReadoutBands + 1), Error);
}

// Through a lens, each sensor pixel samples the pinhole render at the
// undistorted position of its centre (lens_distortion.h): the pinhole pixel
// there must be in the band of the sensor pixel's row (away from the band
// boundaries, where the nearest pinhole pixel may be across one).
TEST(RollingShutter, ThroughALensAPinholePixelTakesTheBandOfItsSensorRow) {
  const Intrinsics sensor = LoadRig(SourcePath("scenes/rig-distorted.json")).left.intrinsics;
  const LensResampler lens(sensor, LensResampler::RequiredMargin(sensor, "left"), "left");
  const Intrinsics& pinhole = lens.pinhole();
  const int count = 16;
  const ReadoutBands bands(sensor, pinhole, count);
  LinearImage marked{pinhole.width_px, pinhole.height_px,
                     std::vector<float>(static_cast<size_t>(pinhole.width_px) * pinhole.height_px * 3, -1.0f)};
  for (int b = 0; b < count; ++b) {
    LinearImage band = marked;
    std::fill(band.rgb.begin(), band.rgb.end(), static_cast<float>(b));
    bands.Composite(b, band, marked);
  }
  size_t checked = 0;
  for (int y = 0; y < sensor.height_px; y += 7) {
    const double band_position = (y + 0.5) * count / sensor.height_px;
    if (std::abs(band_position - std::round(band_position)) * sensor.height_px / count < 2.0) continue;
    for (int x = 0; x < sensor.width_px; x += 13) {
      const Eigen::Vector2d d((x - sensor.cx_px) / sensor.fx_px, (y - sensor.cy_px) / sensor.fy_px);
      const std::optional<Eigen::Vector2d> u = Undistort(sensor.distortion, d);
      ASSERT_TRUE(u.has_value());
      const int pu = static_cast<int>(std::lround(pinhole.fx_px * u->x() + pinhole.cx_px));
      const int pv = static_cast<int>(std::lround(pinhole.fy_px * u->y() + pinhole.cy_px));
      ASSERT_TRUE(pu >= 0 && pu < pinhole.width_px && pv >= 0 && pv < pinhole.height_px);
      EXPECT_EQ(marked.rgb[(static_cast<size_t>(pv) * pinhole.width_px + pu) * 3],
                static_cast<float>(ReadoutBand(y, sensor.height_px, count)))
          << "sensor pixel " << x << ", " << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000u);
  // Every pinhole pixel is in one band.
  for (float v : marked.rgb) ASSERT_GE(v, 0.0f);
}

// The rig.json cameras with a noise-free sensor, global or rolling shutter.
std::filesystem::path WriteRig(const std::filesystem::path& dir, const std::string& name, double readout_ms) {
  nlohmann::json rig = nlohmann::json::parse(ReadFileBytes(SourcePath("scenes/rig.json")));
  rig["schema"] = "aar-rig/3";
  rig["sensor"] = {{"exposure_e", 1e7}, {"full_well_e", 2e7}, {"read_noise_e", 0.0}, {"prnu", 0.0},
                   {"dsnu_e", 0.0},     {"adc_bits", 16},     {"black_level_dn", 0}};
  if (readout_ms > 0.0) rig["sensor"]["readout_ms"] = readout_ms;
  const std::filesystem::path path = dir / name;
  WriteFileAtomic(path, rig.dump(1));
  return path;
}

std::filesystem::path Render(const std::filesystem::path& out, const std::filesystem::path& rig,
                             const std::filesystem::path& flight_path, const std::string& frames) {
  RenderJobOptions o;
  o.output = out;
  o.rig = rig;
  o.receiver_model = SourcePath("scenes/c12.glb");
  o.tanker_model = SourcePath("scenes/kc46.glb");
  o.flight_path = flight_path;
  o.selection = ParseFrameSelection(frames, "");
  o.msaa = 1;
  o.depth = true;
  o.readout_bands = 32;
  o.progress = false;
  RenderFlightPathJob(o);
  return out;
}

// A receiver that does not move renders the same with either shutter: the
// bands' seams add nothing. Moving sideways at 40 m/s in region C, each row
// sees it where it is at the row's band instant: its left edge in the
// silhouette and in the colour moves by the projection's change between the
// sample time and that instant (up to 7 px at the receiver's top and bottom rows).
TEST(RollingShutter, EachRowSeesTheReceiverAtItsOwnInstant) {
  TempDir dir;
  const auto global = WriteRig(dir.path(), "global.json", 0.0), rolling = WriteRig(dir.path(), "rolling.json", 30.0);
  const std::filesystem::path still_path = dir / "still.csv", moving_path = dir / "moving.csv";
  WriteFileAtomic(still_path, "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n0.0,-47.71,0.0,-18.9,0,0,0\n");
  WriteFileAtomic(moving_path,
                  "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n0.0,-47.71,-20.0,-18.9,0,0,0\n"
                  "0.5,-47.71,0.0,-18.9,0,0,0\n1.0,-47.71,20.0,-18.9,0,0,0\n");
  const auto still_g = Render(dir / "still-g", global, still_path, "0:1");
  const auto still_r = Render(dir / "still-r", rolling, still_path, "0:1");
  for (const char* file : {"000000_left.png", "000000_right.png", "000000_left_silhouette.png"}) {
    EXPECT_EQ(ReadFileBytes(still_g / kFramesDir / file), ReadFileBytes(still_r / kFramesDir / file)) << file;
  }
  const nlohmann::json manifest = nlohmann::json::parse(ReadFileBytes(still_r / kManifestName));
  EXPECT_EQ(manifest.at("frames").at("rolling_shutter").at("bands"), 32);
  EXPECT_EQ(manifest.at("image").at("sensor").at("readout_ms"), 30.0);
  EXPECT_FALSE(nlohmann::json::parse(ReadFileBytes(still_g / kManifestName)).at("frames").contains("rolling_shutter"));

  const auto moving_g = Render(dir / "moving-g", global, moving_path, "1:2");
  const auto moving_r = Render(dir / "moving-r", rolling, moving_path, "1:2");
  const StereoRig rig = LoadRig(global);
  const Eigen::Isometry3d camera_from_tanker = rig.left.tanker_from_camera.inverse();
  const auto column_at = [&](double offset_s) {  // the receiver's origin in the left image, offset_s from the sample
    return rig.left.intrinsics.Project(camera_from_tanker * Eigen::Vector3d(-47.71, 40.0 * offset_s, -18.9))->x();
  };
  const std::vector<double> offsets = ReadoutBandOffsets(30.0, 32);
  const auto read = [](const std::filesystem::path& d, const std::string& file) {
    return cv::imread((d / kFramesDir / ("000001_" + file)).string(), cv::IMREAD_UNCHANGED);
  };
  const cv::Mat sky = cv::imread((still_g / kFramesDir / "000000_left.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(sky.empty());
  const cv::Vec3b sky_code = sky.at<cv::Vec3b>(0, 0);  // the flat sky, in a corner
  // A row's left edge: the first silhouette pixel, or the first colour pixel
  // more than 40 codes from the sky's (-1: none).
  const auto silhouette_edge = [](const cv::Mat& s, int y) {
    for (int x = 0; x < s.cols; ++x)
      if (s.at<uint8_t>(y, x) != 0) return x;
    return -1;
  };
  const auto colour_edge = [&](const cv::Mat& c, int y) {
    for (int x = 0; x < c.cols; ++x) {
      const cv::Vec3b p = c.at<cv::Vec3b>(y, x);
      if (std::abs(p[0] - sky_code[0]) + std::abs(p[1] - sky_code[1]) + std::abs(p[2] - sky_code[2]) > 40) return x;
    }
    return -1;
  };
  const cv::Mat sg = read(moving_g, "left_silhouette.png"), sr = read(moving_r, "left_silhouette.png");
  const cv::Mat cg = read(moving_g, "left.png"), cr = read(moving_r, "left.png");
  size_t rows = 0;
  double worst_silhouette = 0.0, worst_colour = 0.0, largest_shift = 0.0;
  for (int y = 0; y < sg.rows; ++y) {
    const int g = silhouette_edge(sg, y), r = silhouette_edge(sr, y), gc = colour_edge(cg, y), rc = colour_edge(cr, y);
    if (g < 0 || r < 0 || gc < 0 || rc < 0) continue;
    const double expected = column_at(offsets[ReadoutBand(y, sg.rows, 32)]) - column_at(0.0);
    worst_silhouette = std::max(worst_silhouette, std::abs(r - g - expected));
    worst_colour = std::max(worst_colour, std::abs(rc - gc - expected));
    largest_shift = std::max(largest_shift, std::abs(expected));
    ++rows;
  }
  std::printf("%zu rows: largest shift %.2f px; worst edge error: silhouette %.2f px, colour %.2f px\n", rows,
              largest_shift, worst_silhouette, worst_colour);
  EXPECT_GT(rows, 100u);
  EXPECT_GT(largest_shift, 6.0);
  // The whole-pixel edge and the receiver's depth spread about its origin.
  EXPECT_LT(worst_silhouette, 1.5);
  EXPECT_LT(worst_colour, 1.5);
}

}  // namespace
}  // namespace aar
