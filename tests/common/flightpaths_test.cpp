// The flight-path generators (flightpaths/flight_path_generator.h), the
// committed CSV files they produce, and aar::ReadFlightPath's error reporting.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/flight_path.h"
#include "aar/region.h"
#include "aar/rig.h"
#include "flight_path_generator.h"

namespace aar {
namespace {

namespace fp = aar::flightpaths;

const std::filesystem::path kSourceDir = AAR_SOURCE_DIR;

const StereoRig& Rig() {
  static const StereoRig rig = LoadRig(kSourceDir / "scenes" / "rig.json");
  return rig;
}

double Range(const FlightSample& s) { return fp::RangeFromLeftCamera(Rig(), s.tanker_from_receiver); }

bool HasHoldNear(const std::vector<fp::Hold>& holds, double range_m) {
  return std::any_of(holds.begin(), holds.end(), [&](const fp::Hold& h) {
    return std::abs(h.mean_range_m - range_m) < 0.5 && h.duration_s >= 5.0;
  });
}

TEST(FlightPaths, ConopsCoversRegionsAndHolds) {
  const std::vector<FlightSample> path = fp::GenerateConops(Rig());
  ASSERT_GE(path.size(), 500u);
  std::map<std::string, int> per_region;
  for (const FlightSample& s : path) ++per_region[RegionForRange(Range(s))];
  EXPECT_GE(per_region["A"], 30);
  EXPECT_GE(per_region["B"], 30);
  EXPECT_GE(per_region["C"], 30);
  EXPECT_EQ(per_region["none"], 0);

  EXPECT_GE(Range(path.front()), 170.0);
  EXPECT_LE(Range(path.front()), 180.0);
  EXPECT_GE(Range(path.back()), 31.5);
  EXPECT_LE(Range(path.back()), 33.0);
  // The path ends at the contact position (within the standoff and wander).
  EXPECT_LT((path.back().tanker_from_receiver.translation_m - Rig().contact_position_m).norm(), 0.05);

  const std::vector<fp::Hold> holds = fp::FindHolds(Rig(), path);
  EXPECT_TRUE(HasHoldNear(holds, 49.0));
  EXPECT_TRUE(HasHoldNear(holds, 34.0));
  EXPECT_TRUE(HasHoldNear(holds, 32.0));
  for (const fp::Hold& hold : holds) {
    EXPECT_LT(hold.range_spread_m, 0.1) << "hold near " << hold.mean_range_m << " m is not near-stationary";
  }

  for (const FlightSample& s : path) {
    EXPECT_LE(std::abs(s.tanker_from_receiver.roll_deg), 5.0);
    EXPECT_LE(std::abs(s.tanker_from_receiver.pitch_deg), 5.0);
    EXPECT_LE(std::abs(s.tanker_from_receiver.yaw_deg), 5.0);
  }
}

TEST(FlightPaths, ConopsIsUniformSmoothAndClosing) {
  const std::vector<FlightSample> path = fp::GenerateConops(Rig());
  const double dt = path[1].time_s - path[0].time_s;
  EXPECT_DOUBLE_EQ(path[0].time_s, 0.0);
  EXPECT_GT(dt, 0.0);
  for (size_t i = 1; i < path.size(); ++i) {
    const Pose& a = path[i - 1].tanker_from_receiver;
    const Pose& b = path[i].tanker_from_receiver;
    ASSERT_NEAR(path[i].time_s - path[i - 1].time_s, dt, 1e-9) << "sample " << i;
    // Closure never faster than a few m/s; the range never opens by more than the wander.
    EXPECT_LT((b.translation_m - a.translation_m).norm() / dt, 3.0) << "sample " << i;
    EXPECT_LT(Range(path[i]) - Range(path[i - 1]), 0.02) << "sample " << i;
    // Attitude changes smoothly (well under 1 deg/s).
    EXPECT_LT(std::abs(b.roll_deg - a.roll_deg) / dt, 1.0) << "sample " << i;
    EXPECT_LT(std::abs(b.pitch_deg - a.pitch_deg) / dt, 1.0) << "sample " << i;
    EXPECT_LT(std::abs(b.yaw_deg - a.yaw_deg) / dt, 1.0) << "sample " << i;
  }
  // Slow in region C.
  for (size_t i = 1; i < path.size(); ++i) {
    if (RegionForRange(Range(path[i])) == "C") {
      EXPECT_LT((Range(path[i - 1]) - Range(path[i])) / dt, 0.5);
    }
  }
}

TEST(FlightPaths, ConopsReceiverStaysInView) {
  const std::vector<FlightSample> path = fp::GenerateConops(Rig());
  size_t fully = 0;
  for (const FlightSample& s : path) {
    const fp::BoxVisibility vis = fp::ComputeBoxVisibility(Rig(), fp::ReceiverBox{}, s.tanker_from_receiver);
    EXPECT_TRUE(vis.reference_in_both) << "t = " << s.time_s;
    fully += vis.FullyInBoth() ? 1 : 0;
  }
  EXPECT_GE(static_cast<double>(fully), 0.9 * static_cast<double>(path.size()));
}

TEST(FlightPaths, CharacterizationSpreadsThroughView) {
  const std::vector<FlightSample> positions = fp::GenerateCharacterization(Rig());
  ASSERT_EQ(positions.size(), 558u);
  const double fit_range = fp::MinimumFitRange(Rig(), fp::ReceiverBox{});
  EXPECT_GT(fit_range, 10.0);
  EXPECT_LT(fit_range, 30.0);
  std::map<std::string, int> per_bin;
  double u_min = 1e9, u_max = -1e9, v_min = 1e9, v_max = -1e9;
  for (size_t i = 0; i < positions.size(); ++i) {
    const FlightSample& s = positions[i];
    const double r = Range(s);
    EXPECT_DOUBLE_EQ(s.time_s, static_cast<double>(i));
    EXPECT_GE(r, 10.0);
    EXPECT_LE(r, 110.0);
    if (i > 0) {
      EXPECT_GT(r, Range(positions[i - 1])) << "ranges must ascend";
    }
    EXPECT_EQ(s.tanker_from_receiver.roll_deg, 0.0);
    EXPECT_EQ(s.tanker_from_receiver.pitch_deg, 0.0);
    EXPECT_EQ(s.tanker_from_receiver.yaw_deg, 0.0);
    const fp::BoxVisibility vis = fp::ComputeBoxVisibility(Rig(), fp::ReceiverBox{}, s.tanker_from_receiver);
    EXPECT_TRUE(vis.reference_in_both) << "sample " << i;
    if (r > fit_range + 0.01) {
      EXPECT_TRUE(vis.FullyInBoth()) << "sample " << i << " at " << r << " m";
    }
    ++per_bin[RangeBinForRange(r)];
    if (r >= 60.0) {
      const Eigen::Vector3d in_left = Rig().left.tanker_from_camera.inverse() * s.tanker_from_receiver.translation_m;
      const Eigen::Vector2d px = *Rig().left.intrinsics.Project(in_left);
      u_min = std::min(u_min, px.x());
      u_max = std::max(u_max, px.x());
      v_min = std::min(v_min, px.y());
      v_max = std::max(v_max, px.y());
    }
  }
  EXPECT_GE(per_bin["20-60"], 150);
  EXPECT_GE(per_bin["60-110"], 150);
  // At long range the positions reach across most of the image.
  EXPECT_LT(u_min, 200.0);
  EXPECT_GT(u_max, 824.0);
  EXPECT_LT(v_min, 150.0);
  EXPECT_GT(v_max, 618.0);
}

TEST(FlightPaths, GenerationIsDeterministic) {
  EXPECT_EQ(FormatFlightPath(fp::GenerateConops(Rig())), FormatFlightPath(fp::GenerateConops(Rig())));
  EXPECT_EQ(FormatFlightPath(fp::GenerateCharacterization(Rig())),
            FormatFlightPath(fp::GenerateCharacterization(Rig())));
}

// Held-out variants: a seed gives one path, always; seeds differ; every region and both holds are there, and the
// receiver stays in view.
TEST(FlightPaths, ConopsVariantsAreSeededAndStayInView) {
  const std::string first = FormatFlightPath(fp::GenerateConops(Rig(), fp::ConopsVariantOptions(Rig(), 1)));
  EXPECT_EQ(first, FormatFlightPath(fp::GenerateConops(Rig(), fp::ConopsVariantOptions(Rig(), 1))));
  EXPECT_NE(first, FormatFlightPath(fp::GenerateConops(Rig(), fp::ConopsVariantOptions(Rig(), 2))));
  EXPECT_NE(first, FormatFlightPath(fp::GenerateConops(Rig())));
  for (const uint64_t seed : {1u, 2u, 3u, 4u}) {
    const std::vector<FlightSample> path = fp::GenerateConops(Rig(), fp::ConopsVariantOptions(Rig(), seed));
    std::map<std::string, int> per_region;
    for (const FlightSample& s : path) {
      ++per_region[RegionForRange(Range(s))];
      ASSERT_TRUE(fp::ComputeBoxVisibility(Rig(), fp::ReceiverBox{}, s.tanker_from_receiver).FullyInBoth())
          << "seed " << seed << " t " << s.time_s;
    }
    for (const char* region : {"A", "B", "C"}) EXPECT_GT(per_region[region], 50) << "seed " << seed << region;
    const double contact_range_m = (Rig().contact_position_m - Rig().left.tanker_from_camera.translation()).norm();
    EXPECT_NEAR(Range(path.back()), contact_range_m, 0.05) << "seed " << seed;  // ends at the contact position
    const std::vector<fp::Hold> holds = fp::FindHolds(Rig(), path);
    EXPECT_GE(holds.size(), 3u) << "seed " << seed;
  }
}

TEST(FlightPaths, CommittedCsvFilesMatchGenerator) {
  const std::vector<std::pair<std::string, std::vector<FlightSample>>> files = {
      {"conops.csv", fp::GenerateConops(Rig())},
      {"characterization.csv", fp::GenerateCharacterization(Rig())},
  };
  for (const auto& [name, generated] : files) {
    const std::filesystem::path path = kSourceDir / "flightpaths" / name;
    ASSERT_TRUE(std::filesystem::exists(path)) << path << " missing: run aar-make-flightpaths";
    EXPECT_EQ(ReadFileBytes(path), FormatFlightPath(generated))
        << path << " is stale: run aar-make-flightpaths --rig scenes/rig.json --out flightpaths/";
    const std::vector<FlightSample> read = ReadFlightPath(path);
    ASSERT_EQ(read.size(), generated.size()) << path;
    for (size_t i = 0; i < read.size(); ++i) {
      EXPECT_EQ(read[i].time_s, generated[i].time_s);
      EXPECT_EQ(read[i].tanker_from_receiver.translation_m, generated[i].tanker_from_receiver.translation_m);
      EXPECT_EQ(read[i].tanker_from_receiver.roll_deg, generated[i].tanker_from_receiver.roll_deg);
      EXPECT_EQ(read[i].tanker_from_receiver.pitch_deg, generated[i].tanker_from_receiver.pitch_deg);
      EXPECT_EQ(read[i].tanker_from_receiver.yaw_deg, generated[i].tanker_from_receiver.yaw_deg);
    }
  }
}

// conops-level.csv is generated for the thesis rig (issue 9), not for rig.json.
TEST(FlightPaths, CommittedLevelCsvMatchesGenerator) {
  const StereoRig thesis = LoadRig(kSourceDir / "scenes" / "rig-thesis.json");
  const std::filesystem::path path = kSourceDir / "flightpaths" / "conops-level.csv";
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " missing: run aar-make-flightpaths";
  EXPECT_EQ(ReadFileBytes(path), FormatFlightPath(fp::GenerateConops(thesis, fp::LevelConopsOptions())))
      << path << " is stale: run aar-make-flightpaths --rig scenes/rig-thesis.json --out flightpaths/ --paths "
      << "conops-level";
  // Level at the contact height from level_range_m in (within the wander).
  for (const FlightSample& s : ReadFlightPath(path)) {
    if (fp::RangeFromLeftCamera(thesis, s.tanker_from_receiver) < fp::LevelConopsOptions().level_range_m) {
      EXPECT_NEAR(s.tanker_from_receiver.translation_m.z(), thesis.contact_position_m.z(), 0.01) << s.time_s;
    }
  }
}

TEST(FlightPaths, RejectsInconsistentOptions) {
  fp::CharacterizationOptions characterization;
  characterization.count = 557;
  EXPECT_THROW(fp::GenerateCharacterization(Rig(), characterization), Error);
  fp::ConopsOptions conops;
  conops.legs.back().end_range_m = 40.0;  // must end at the contact position
  EXPECT_THROW(fp::GenerateConops(Rig(), conops), Error);
  conops = {};
  conops.legs[1].end_range_m = 130.0;  // ranges must decrease
  EXPECT_THROW(fp::GenerateConops(Rig(), conops), Error);
  conops = {};
  conops.legs[0].hold_s = 5.0;  // a hold needs the leg to end at rest
  EXPECT_THROW(fp::GenerateConops(Rig(), conops), Error);
}

// aar::ReadFlightPath errors name the file and the line.
class FlightPathCsv : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("aar_flightpath_" + std::string(info->name()) + "_" + std::to_string(::getpid()) + ".csv");
  }
  void TearDown() override { std::filesystem::remove(path_); }

  // Writes `text`, expects ReadFlightPath to throw, returns the message.
  std::string ErrorFor(const std::string& text) {
    {
      std::ofstream out(path_);
      out << text;
    }
    try {
      ReadFlightPath(path_);
    } catch (const Error& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return "";
  }

  std::filesystem::path path_;
};

const std::string kHeader = std::string(kFlightPathHeader) + "\n";
const std::string kGoodLine = "0.000,-47.7,0.0,-18.9,0.0,0.0,0.0\n";

TEST_F(FlightPathCsv, ReadsValidFile) {
  {
    std::ofstream out(path_);
    out << kHeader << kGoodLine << "0.5,-47.6,0.1,-18.8,1,2,3\r\n";
  }
  const std::vector<FlightSample> samples = ReadFlightPath(path_);
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_DOUBLE_EQ(samples[1].time_s, 0.5);
  EXPECT_DOUBLE_EQ(samples[1].tanker_from_receiver.yaw_deg, 3.0);
}

TEST_F(FlightPathCsv, RejectsWrongHeader) {
  const std::string message = ErrorFor("time,x,y,z,roll,pitch,yaw\n" + kGoodLine);
  EXPECT_NE(message.find(path_.string() + ":1:"), std::string::npos) << message;
  EXPECT_NE(message.find("header"), std::string::npos) << message;
}

TEST_F(FlightPathCsv, RejectsNaN) {
  const std::string message = ErrorFor(kHeader + kGoodLine + "0.5,-47.6,nan,-18.8,0,0,0\n");
  EXPECT_NE(message.find(path_.string() + ":3:"), std::string::npos) << message;
  EXPECT_NE(message.find("y_m"), std::string::npos) << message;
  EXPECT_NE(message.find("not a finite number"), std::string::npos) << message;
}

TEST_F(FlightPathCsv, RejectsTextInNumberField) {
  const std::string message = ErrorFor(kHeader + "0.0,-47.7,0.0,-18.9,zero,0.0,0.0\n");
  EXPECT_NE(message.find(path_.string() + ":2:"), std::string::npos) << message;
  EXPECT_NE(message.find("roll_deg"), std::string::npos) << message;
  EXPECT_NE(message.find("'zero'"), std::string::npos) << message;
}

TEST_F(FlightPathCsv, RejectsWrongColumnCount) {
  const std::string message = ErrorFor(kHeader + kGoodLine + kGoodLine + "1.0,-47.5,0.0,-18.7,0.0,0.0\n");
  EXPECT_NE(message.find(path_.string() + ":4:"), std::string::npos) << message;
  EXPECT_NE(message.find("expected 7 fields, found 6"), std::string::npos) << message;
}

}  // namespace
}  // namespace aar
