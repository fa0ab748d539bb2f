// The rig's sensor block (common/sensor.h, schema aar-rig/3): defaults,
// round trip, the schema gate, refusals naming the file and the field, and
// the committed rigs.

#include "aar/sensor.h"

#include <gtest/gtest.h>

#include <functional>
#include <nlohmann/json.hpp>

#include "../test_support.h"
#include "aar/error.h"
#include "aar/rig.h"

namespace aar {
namespace {

using test::SourcePath;

using test::ErrorOf;

nlohmann::json RigWithSensor(const nlohmann::json& sensor) {
  nlohmann::json j = RigToJson(LoadRig(SourcePath("scenes/rig.json")));
  j["schema"] = "aar-rig/3";
  j["sensor"] = sensor;
  return j;
}

TEST(RigSensor, MissingFieldsTakeTheDefaultsAndTheBlockRoundTrips) {
  const StereoRig rig = RigFromJson(RigWithSensor({{"exposure_e", 1000.0}, {"bayer", "rggb"}}), "r.json");
  ASSERT_TRUE(rig.sensor.has_value());
  const SensorParams defaults;
  EXPECT_EQ(rig.sensor->exposure_e, 1000.0);
  EXPECT_EQ(rig.sensor->bayer, BayerPattern::kRggb);
  EXPECT_EQ(rig.sensor->seed, defaults.seed);
  EXPECT_EQ(rig.sensor->full_well_e, defaults.full_well_e);
  EXPECT_EQ(rig.sensor->read_noise_e, defaults.read_noise_e);
  EXPECT_EQ(rig.sensor->adc_bits, defaults.adc_bits);
  EXPECT_EQ(rig.sensor->blur_sigma_px, 0.0);
  EXPECT_NEAR(defaults.GainDnPerElectron(), (4095.0 - 64.0) / 10000.0, 1e-15);
  const nlohmann::json written = RigToJson(rig);
  EXPECT_EQ(written.at("schema"), "aar-rig/3");
  EXPECT_EQ(RigToJson(RigFromJson(written, "again.json")), written);
  EXPECT_FALSE(written.at("sensor").contains("glare_fraction"));  // no glare: the record sensors always had
  const StereoRig glare = RigFromJson(RigWithSensor({{"glare_fraction", 0.02}, {"glare_core_deg", 0.8}}), "g.json");
  EXPECT_EQ(glare.sensor->glare_fraction, 0.02);
  EXPECT_EQ(RigToJson(glare).at("sensor").at("glare_core_deg"), 0.8);
  EXPECT_EQ(RigToJson(RigFromJson(RigToJson(glare), "again.json")), RigToJson(glare));
  EXPECT_FALSE(written.at("sensor").contains("blooming"));  // no blooming or smear: the same
  EXPECT_FALSE(written.at("sensor").contains("smear"));
  const StereoRig ccd = RigFromJson(RigWithSensor({{"blooming", 0.7}, {"smear", 0.002}}), "c.json");
  EXPECT_EQ(ccd.sensor->blooming, 0.7);
  EXPECT_EQ(RigToJson(ccd).at("sensor").at("smear"), 0.002);
  EXPECT_EQ(RigToJson(RigFromJson(RigToJson(ccd), "again.json")), RigToJson(ccd));
  EXPECT_FALSE(written.at("sensor").contains("flare_ghosts"));
  const StereoRig flare = RigFromJson(
      RigWithSensor({{"flare_ghosts", {{{"position", -0.8}, {"radius_px", 25.0}, {"fraction", 2e-4}}}}}), "f.json");
  ASSERT_EQ(flare.sensor->flare_ghosts.size(), 1u);
  EXPECT_EQ(flare.sensor->flare_ghosts[0].position, -0.8);
  EXPECT_EQ(flare.sensor->flare_ghosts[0].radius_px, 25.0);
  EXPECT_EQ(flare.sensor->flare_ghosts[0].fraction, 2e-4);
  EXPECT_EQ(RigToJson(RigFromJson(RigToJson(flare), "again.json")), RigToJson(flare));
}

// Off by default: the committed pinhole rig has no sensor and is written back
// as aar-rig/1; the committed noisy rig has one.
TEST(RigSensor, CommittedRigsHaveASensorOnlyWhereTheyDeclareIt) {
  const StereoRig clean = LoadRig(SourcePath("scenes/rig.json"));
  EXPECT_FALSE(clean.sensor.has_value());
  EXPECT_EQ(RigToJson(clean).at("schema"), "aar-rig/1");
  EXPECT_FALSE(RigToJson(clean).contains("sensor"));
  const StereoRig noisy = LoadRig(SourcePath("scenes/rig-noisy.json"));
  ASSERT_TRUE(noisy.sensor.has_value());
  EXPECT_EQ(noisy.sensor->exposure_e, 2000.0);
  EXPECT_EQ(noisy.sensor->blur_sigma_px, 0.5);
  EXPECT_EQ(noisy.sensor->bayer, BayerPattern::kRggb);
}

TEST(RigSensor, BadSensorEntriesAreRefusedNamingTheFileAndField) {
  nlohmann::json v2 = RigWithSensor(nlohmann::json::object());
  v2["schema"] = "aar-rig/2";
  EXPECT_NE(ErrorOf([&] { RigFromJson(v2, "r.json"); }).find("r.json: 'sensor' needs schema \"aar-rig/3\""),
            std::string::npos);
  const std::vector<std::pair<nlohmann::json, std::string>> bad = {
      {{{"read_noise_e", -1.0}}, "r.json: sensor.read_noise_e -1 must be in [0, 1e9]"},
      {{{"exposure_e", 0.0}}, "r.json: sensor.exposure_e 0 must be in (0, 1e9]"},
      {{{"exposur_e", 100.0}}, "r.json: sensor.exposur_e is not a sensor field"},
      {{{"adc_bits", 20}}, "r.json: sensor.adc_bits 20 is outside [8, 16]"},
      {{{"adc_bits", 10.5}}, "r.json: sensor.adc_bits must be an integer"},
      {{{"prnu", "1%"}}, "r.json: sensor.prnu must be a number"},
      {{{"prnu", 0.7}}, "r.json: sensor.prnu 0.7 must be in [0, 0.5]"},
      {{{"adc_bits", 8}, {"black_level_dn", 300}}, "r.json: sensor.black_level_dn 300 must be in [0, 2^adc_bits - 2]"},
      {{{"blur_sigma_px", 12.0}}, "r.json: sensor.blur_sigma_px 12 must be in [0, 10]"},
      {{{"bayer", "bggr"}}, "r.json: sensor.bayer \"bggr\" must be \"none\" or \"rggb\""},
      {{{"seed", -3}}, "r.json: sensor.seed -3 is outside"},
      {{{"glare_fraction", 0.5}}, "r.json: sensor.glare_fraction 0.5 must be in [0, 0.2]"},
      {{{"glare_fraction", 0.02}, {"glare_core_deg", 0.0}}, "r.json: sensor.glare_core_deg 0 must be in [0.01, 10]"},
      {{{"blooming", 1.5}}, "r.json: sensor.blooming 1.5 must be in [0, 1]"},
      {{{"smear", -0.01}}, "r.json: sensor.smear -0.01 must be in [0, 0.1]"},
      {{{"flare_ghosts", 3}}, "r.json: sensor.flare_ghosts must be an array of ghosts"},
      {{{"flare_ghosts", {{{"position", 0.5}, {"radius_px", 10.0}}}}}, "r.json: sensor.flare_ghosts[0] lacks fraction"},
      {{{"flare_ghosts", {{{"position", 0.5}, {"radius_px", 10.0}, {"fraction", 1e-4}, {"tint", 1}}}}},
       "r.json: sensor.flare_ghosts[0].tint is not a ghost field"},
      {{{"flare_ghosts", {{{"position", "a"}, {"radius_px", 10.0}, {"fraction", 1e-4}}}}},
       "r.json: sensor.flare_ghosts[0].position must be a finite number"},
      {{{"flare_ghosts", {{{"position", 3.0}, {"radius_px", 10.0}, {"fraction", 1e-4}}}}},
       "r.json: sensor.flare_ghosts[0].position 3 must be in [-2, 2]"},
      {{{"flare_ghosts", {{{"position", 0.5}, {"radius_px", 10.0}, {"fraction", 0.1}}}}},
       "r.json: sensor.flare_ghosts[0].fraction 0.1 must be in (0, 0.01]"},
  };
  for (const auto& [sensor, message] : bad) {
    const std::string error = ErrorOf([&] { RigFromJson(RigWithSensor(sensor), "r.json"); });
    EXPECT_NE(error.find(message), std::string::npos) << sensor.dump() << " -> " << error;
  }
  EXPECT_NE(ErrorOf([&] { RigFromJson(RigWithSensor(3), "r.json"); }).find("r.json: sensor must be an object"),
            std::string::npos);
}

}  // namespace
}  // namespace aar
