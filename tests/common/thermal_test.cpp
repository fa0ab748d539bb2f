// The LWIR camera's radiometry and rig block (common/thermal.h): Planck's
// law over a band against the Stefan-Boltzmann law and published band
// fractions, the brightness-temperature table against the exact radiance,
// and the rig's "lwir" block (schema aar-rig/4) read, written and refused.

#include "aar/thermal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "../test_support.h"
#include "aar/error.h"
#include "aar/rig.h"

namespace aar {
namespace {

using test::ErrorOf;
using test::SourcePath;

constexpr double kPi = 3.14159265358979323846;
constexpr double kStefanBoltzmann = 5.670374419e-8;  // W m^-2 K^-4, CODATA 2018

// Over nearly all wavelengths the band radiance is sigma T^4 / pi.
TEST(Thermal, TheWholeSpectrumGivesTheStefanBoltzmannLaw) {
  for (double t : {250.0, 300.0, 600.0}) {
    const double whole = BandRadiance(t, 0.3, 1000.0, 200000);
    EXPECT_NEAR(whole / (kStefanBoltzmann * t * t * t * t / kPi), 1.0, 2e-4) << t;
  }
}

// The fraction of a blackbody's emission below lambda T (Incropera and
// DeWitt, Fundamentals of Heat and Mass Transfer, Table 12.1): 0.066728 at
// 2,000 um K, 0.273232 at 3,000, 0.480877 at 4,000, 0.633747 at 5,000.
TEST(Thermal, BandFractionsAreThePublishedOnes) {
  const double t = 1000.0, total = kStefanBoltzmann * t * t * t * t / kPi;
  const std::pair<double, double> table[] = {
      {2000.0, 0.066728}, {3000.0, 0.273232}, {4000.0, 0.480877}, {5000.0, 0.633747}};
  for (const auto& [lambda_t, fraction] : table) {
    EXPECT_NEAR(BandRadiance(t, 0.3, lambda_t / t, 20000) / total, fraction, 1e-4) << lambda_t;
  }
  // 8-14 um at 300 K: F(4200) - F(2400), 0.516 - 0.140 of sigma T^4 / pi.
  EXPECT_NEAR(BandRadiance(300.0, 8.0, 14.0), 54.93, 0.01);
}

TEST(Thermal, TheTableInvertsTheRadianceAndGivesItsSlope) {
  const BandRadianceTable table(8.0, 14.0);
  for (double t = 150.0; t <= 700.0; t += 13.37) {
    const double exact = BandRadiance(t, 8.0, 14.0);
    EXPECT_NEAR(table.Radiance(t) / exact, 1.0, 1e-6) << t;  // linear between 0.05 K steps
    EXPECT_NEAR(table.BrightnessTemperature(exact), t, 1e-3) << t;
    const double slope = (BandRadiance(t + 0.01, 8.0, 14.0) - BandRadiance(t - 0.01, 8.0, 14.0)) / 0.02;
    EXPECT_NEAR(table.Slope(t) / slope, 1.0, 1e-4) << t;
  }
  EXPECT_EQ(table.BrightnessTemperature(0.0), 20.0);  // clamped to the table's range
}

nlohmann::json RigWithLwir(const nlohmann::json& lwir, const char* schema = "aar-rig/4") {
  nlohmann::json j = nlohmann::json::parse(R"({"image_width": 640, "image_height": 512, "cameras": {
    "left": {"fx_px": 600, "fy_px": 600, "cx_px": 319.5, "cy_px": 255.5,
             "tanker_from_camera": {"translation_m": [0, 0, 0], "rotation": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}},
    "right": {"fx_px": 600, "fy_px": 600, "cx_px": 319.5, "cy_px": 255.5,
              "tanker_from_camera": {"translation_m": [0, 0.5, 0], "rotation": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}}}})");
  j["schema"] = schema;
  j["lwir"] = lwir;
  return j;
}

TEST(Thermal, TheRigsLwirBlockRoundTripsAndBadOnesAreRefused) {
  const StereoRig rig = RigFromJson(RigWithLwir({{"netd_mk", 40.0}, {"band_um", {7.5, 13.5}}}), "r.json");
  ASSERT_TRUE(rig.lwir.has_value());
  EXPECT_EQ(rig.lwir->netd_mk, 40.0);
  EXPECT_EQ(rig.lwir->band_min_um, 7.5);
  EXPECT_EQ(rig.lwir->nonuniformity_mk, 0.0);
  const nlohmann::json written = RigToJson(rig);
  EXPECT_EQ(written.at("schema"), "aar-rig/4");
  EXPECT_EQ(RigToJson(RigFromJson(written, "again.json")), written);
  const StereoRig committed = LoadRig(SourcePath("scenes/rig-lwir.json"));
  ASSERT_TRUE(committed.lwir.has_value());
  EXPECT_EQ(committed.lwir->netd_mk, 50.0);
  EXPECT_EQ(committed.left.intrinsics.width_px, 640);

  const std::pair<nlohmann::json, std::string> bad[] = {
      {RigWithLwir(nlohmann::json::object(), "aar-rig/3"), "r.json: 'lwir' needs schema \"aar-rig/4\""},
      {RigWithLwir({{"netd_mk", -1.0}}), "r.json: lwir.netd_mk -1 must be in [0, 10000]"},
      {RigWithLwir({{"band_um", {14.0, 8.0}}}), "r.json: lwir.band_um [14, 8] must lie in [1, 30] um"},
      {RigWithLwir({{"netd", 50.0}}), "r.json: lwir.netd is not a field of the LWIR camera"},
      {RigWithLwir(3), "r.json: lwir must be an object"},
  };
  for (const auto& [j, message] : bad) {
    const std::string error = ErrorOf([&] { RigFromJson(j, "r.json"); });
    EXPECT_NE(error.find(message), std::string::npos) << error;
  }
  nlohmann::json both = RigWithLwir(nlohmann::json::object());
  both["sensor"] = nlohmann::json::object();
  EXPECT_NE(ErrorOf([&] { RigFromJson(both, "r.json"); }).find("a rig's cameras are visible or thermal, not both"),
            std::string::npos);
}

}  // namespace
}  // namespace aar
