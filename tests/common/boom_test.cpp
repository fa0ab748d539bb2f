// The boom's pose (common/include/aar/boom.h), the flight-path columns that
// pose it (7 or 10 columns), and conops-boom.csv against its generator.

#include "aar/boom.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "../test_support.h"
#include "aar/file_io.h"
#include "aar/flight_path.h"
#include "aar/region.h"
#include "aar/rig.h"
#include "flight_path_generator.h"

namespace aar {
namespace {

namespace fp = aar::flightpaths;
using test::ErrorOf;
using test::SourcePath;
using test::TempDir;

constexpr const char* kBoomHeader =
    "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg,boom_pitch_deg,boom_roll_deg,boom_extension_m\n";

std::filesystem::path WriteCsv(const TempDir& dir, const std::string& text) {
  const std::filesystem::path path = dir / "path.csv";
  WriteFileAtomic(path, text);
  return path;
}

TEST(Boom, StowedBoomLiesAftAlongTheTankerAxis) {
  const BoomPose stowed;
  EXPECT_TRUE(BoomNozzleInTanker(stowed).isApprox(kBoomHingeInTanker - Eigen::Vector3d(kBoomNozzleTipM, 0, 0)));
}

TEST(Boom, PitchLowersAndRollSwingsLeftAndExtensionLengthens) {
  const Eigen::Vector3d d = (BoomNozzleInTanker({30.0, 0.0, 0.0}) - kBoomHingeInTanker) / kBoomNozzleTipM;
  EXPECT_NEAR(d.x(), -std::cos(M_PI / 6), 1e-12);
  EXPECT_NEAR(d.z(), -0.5, 1e-12);  // down
  const Eigen::Vector3d rolled = BoomNozzleInTanker({30.0, 10.0, 0.0}) - kBoomHingeInTanker;
  EXPECT_GT(rolled.y(), 0.5);  // to the left (+y)
  const double extended = (BoomNozzleInTanker({30.0, 0.0, 4.0}) - kBoomHingeInTanker).norm();
  EXPECT_NEAR(extended, kBoomNozzleTipM + 4.0, 1e-12);
}

TEST(Boom, PointedAtATargetReachesItWhenInRange) {
  const Eigen::Vector3d target = kBoomHingeInTanker + Eigen::Vector3d(-14.0, 2.0, -8.0);
  const BoomPose pose = fp::BoomPointedAt(target);
  EXPECT_LT((BoomNozzleInTanker(pose) - target).norm(), 1e-9);
}

TEST(Boom, CheckNamesTheValueOutOfRange) {
  EXPECT_EQ(ErrorOf([] {
              BoomPose{50.0, 0.0, 0.0}.Check("p.csv:3");
            }),
            "p.csv:3: boom_pitch_deg 50.0000 must be in [0.0, 45.0]");
  EXPECT_NE(ErrorOf([] { BoomPose{10.0, 0.0, 6.5}.Check("x"); }).find("boom_extension_m 6.5000"), std::string::npos);
  EXPECT_NE(ErrorOf([] { BoomPose{10.0, -30.0, 0.0}.Check("x"); }).find("boom_roll_deg"), std::string::npos);
}

TEST(FlightPathBoom, SevenColumnsHaveNoBoomAndTenColumnsPoseIt) {
  TempDir dir;
  const auto seven = ReadFlightPath(WriteCsv(dir, std::string(kFlightPathHeader) + "\n0,-47,0,-19,0,0,0\n"));
  ASSERT_EQ(seven.size(), 1u);
  EXPECT_FALSE(seven[0].boom.has_value());
  const auto ten = ReadFlightPath(WriteCsv(dir, std::string(kBoomHeader) + "0,-47,0,-19,0,0,0,30.5,-2.25,3\n"));
  ASSERT_EQ(ten.size(), 1u);
  ASSERT_TRUE(ten[0].boom.has_value());
  EXPECT_EQ(ten[0].boom->pitch_deg, 30.5);
  EXPECT_EQ(ten[0].boom->roll_deg, -2.25);
  EXPECT_EQ(ten[0].boom->extension_m, 3.0);
  // Formatting keeps the columns each path has.
  EXPECT_EQ(FormatFlightPath(seven),
            std::string(kFlightPathHeader) + "\n0.000,-47.0000,0.0000,-19.0000,0.0000,0.0000,0.0000\n");
  EXPECT_EQ(FormatFlightPath(ten),
            std::string(kBoomHeader) + "0.000,-47.0000,0.0000,-19.0000,0.0000,0.0000,0.0000,30.5000,-2.2500,3.0000\n");
}

TEST(FlightPathBoom, BadBoomColumnsNameTheFileAndLine) {
  TempDir dir;
  const auto error = [&](const std::string& text) { return ErrorOf([&] { ReadFlightPath(WriteCsv(dir, text)); }); };
  EXPECT_NE(
      error(std::string(kBoomHeader) + "0,-47,0,-19,0,0,0,30,0\n").find("path.csv:2: expected 10 fields, found 9"),
      std::string::npos);
  EXPECT_NE(error(std::string(kBoomHeader) + "0,-47,0,-19,0,0,0,30,0,x\n").find("path.csv:2: field boom_extension_m"),
            std::string::npos);
  EXPECT_NE(error(std::string(kBoomHeader) + "0,-47,0,-19,0,0,0,30,0,1\n1,-47,0,-19,0,0,0,60,0,1\n")
                .find("path.csv:3: boom_pitch_deg 60.0000 must be in [0.0, 45.0]"),
            std::string::npos);
  // Other names or order are not the boom header.
  EXPECT_NE(error("time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg,boom_roll_deg,boom_pitch_deg,boom_extension_m\n")
                .find("path.csv:1: wrong header"),
            std::string::npos);
  EXPECT_NE(error(std::string(kFlightPathHeader) + ",boom_pitch_deg\n0,-47,0,-19,0,0,0,30\n").find("wrong header"),
            std::string::npos);
  // Seven fields under the boom header, ten under the plain one.
  EXPECT_NE(error(std::string(kFlightPathHeader) + "\n0,-47,0,-19,0,0,0,30,0,1\n").find("expected 7 fields, found 10"),
            std::string::npos);
}

TEST(FlightPathBoom, CommittedBoomCsvMatchesGenerator) {
  const StereoRig rig = LoadRig(SourcePath("scenes/rig.json"));
  const std::filesystem::path path = SourcePath("flightpaths/conops-boom.csv");
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " missing: run aar-make-flightpaths";
  EXPECT_EQ(ReadFileBytes(path), FormatFlightPath(fp::AddBoomSchedule(rig, fp::GenerateConops(rig))))
      << path << " is stale: run aar-make-flightpaths --rig scenes/rig.json --out flightpaths/ --paths conops-boom";
  // The receiver flies conops.csv; the boom is stowed far out and lowered in region C.
  const auto boom = ReadFlightPath(path);
  const auto conops = ReadFlightPath(SourcePath("flightpaths/conops.csv"));
  ASSERT_EQ(boom.size(), conops.size());
  for (size_t i = 0; i < boom.size(); ++i) {
    ASSERT_TRUE(boom[i].boom.has_value()) << i;
    EXPECT_TRUE(boom[i].tanker_from_receiver.translation_m == conops[i].tanker_from_receiver.translation_m) << i;
    const double range = fp::RangeFromLeftCamera(rig, boom[i].tanker_from_receiver);
    if (range > fp::BoomScheduleOptions{}.lower_start_range_m) {
      EXPECT_EQ(boom[i].boom->pitch_deg, 0.0) << i;
      EXPECT_EQ(boom[i].boom->extension_m, 0.0) << i;
    }
    if (RegionForRange(range) == "C") {
      EXPECT_GT(boom[i].boom->pitch_deg, 30.0) << i;
    }
  }
}

}  // namespace
}  // namespace aar
