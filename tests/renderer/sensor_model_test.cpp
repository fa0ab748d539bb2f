// The sensor model (renderer/sensor_model.h, optical_blur.h, bayer.h): noise
// statistics against the EMVA 1288 photon-transfer model, the fixed pattern,
// determinism of the counter-based noise, saturation, the Bayer mosaic and
// demosaicing, the Gaussian blur.

#include "aar/renderer/sensor_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <thread>
#include <vector>

#include "aar/renderer/bayer.h"
#include "aar/renderer/optical_blur.h"

namespace aar {
namespace {

LinearImage Flat(int width, int height, float r, float g, float b) {
  LinearImage image;
  image.width = width;
  image.height = height;
  image.rgb.resize(static_cast<size_t>(width) * height * 3);
  for (size_t i = 0; i < image.rgb.size(); i += 3) {
    image.rgb[i] = r;
    image.rgb[i + 1] = g;
    image.rgb[i + 2] = b;
  }
  return image;
}

struct Moments {
  double mean = 0.0;
  double variance = 0.0;
};

Moments MomentsOf(const std::vector<float>& values) {
  Moments m;
  for (float v : values) m.mean += v;
  m.mean /= static_cast<double>(values.size());
  for (float v : values) m.variance += (v - m.mean) * (v - m.mean);
  m.variance /= static_cast<double>(values.size() - 1);
  return m;
}

double Correlation(const std::vector<float>& a, const std::vector<float>& b) {
  const Moments ma = MomentsOf(a), mb = MomentsOf(b);
  double c = 0.0;
  for (size_t i = 0; i < a.size(); ++i) c += (a[i] - ma.mean) * (b[i] - mb.mean);
  return c / static_cast<double>(a.size() - 1) / std::sqrt(ma.variance * mb.variance);
}

// The model's prediction for a flat patch of radiance L, in radiance units
// (EMVA 1288's temporal variance with the fixed pattern and the ADC step added): variance
// in e- = mu + read^2 + dsnu^2 + (prnu mu)^2 + 1 / (12 K^2), mu = L exposure.
double PredictedVariance(const SensorParams& s, double radiance) {
  const double mu = radiance * s.exposure_e;
  const double k = s.GainDnPerElectron();
  const double electrons =
      mu + s.read_noise_e * s.read_noise_e + s.dsnu_e * s.dsnu_e + (s.prnu * mu) * (s.prnu * mu) + 1.0 / (12.0 * k * k);
  return electrons / (s.exposure_e * s.exposure_e);
}

// Flat patches of 256 x 256 pixels x 3 channels (196,608 samples, so the
// variance is known to 0.3 % (one sigma) and the tolerance, 3 %, is ten of
// them): at a bright and a dark level with the defaults, and with each noise
// source alone. The mean is the radiance within four standard errors.
TEST(SensorModel, FlatPatchMeanAndVarianceMatchThePhotonTransferModel) {
  struct Case {
    const char* name;
    SensorParams sensor;
    double radiance;
  };
  std::vector<Case> cases;
  cases.push_back({"defaults, bright", SensorParams{}, 0.6});
  cases.push_back({"defaults, dark", SensorParams{}, 0.004});
  SensorParams shot;  // shot noise alone, a 16-bit ADC (6.5 DN/e-)
  shot.read_noise_e = 0.0;
  shot.prnu = 0.0;
  shot.dsnu_e = 0.0;
  shot.adc_bits = 16;
  shot.black_level_dn = 2000;  // 307 e-: the dark noise below is never clipped at DN 0
  shot.exposure_e = 400.0;
  cases.push_back({"shot noise alone", shot, 0.5});
  SensorParams read = shot;  // read noise dominates at radiance 0.01 (4 e-)
  read.read_noise_e = 20.0;
  cases.push_back({"read noise", read, 0.01});
  SensorParams prnu = shot;  // PRNU dominates
  prnu.exposure_e = 50000.0;
  prnu.full_well_e = 100000.0;
  prnu.prnu = 0.05;
  cases.push_back({"prnu", prnu, 0.8});
  SensorParams dsnu = shot;
  dsnu.dsnu_e = 15.0;
  cases.push_back({"dsnu", dsnu, 0.02});
  for (const Case& c : cases) {
    const LinearImage out =
        ApplySensorModel(Flat(256, 256, c.radiance, c.radiance, c.radiance), c.sensor, SensorExposure{0, 7, 0});
    const Moments m = MomentsOf(out.rgb);
    const double predicted = PredictedVariance(c.sensor, c.radiance);
    std::printf("%s: radiance %.4f mean %.6f, variance %.4g predicted %.4g (ratio %.4f)\n", c.name, c.radiance, m.mean,
                m.variance, predicted, m.variance / predicted);
    EXPECT_NEAR(m.mean, c.radiance, 4.0 * std::sqrt(predicted / static_cast<double>(out.rgb.size()))) << c.name;
    EXPECT_NEAR(m.variance / predicted, 1.0, 0.03) << c.name;
  }
}

// Photo-electrons stop at the full well: with the defaults (10,000 e-,
// exposure 5,000 e-) no pixel reads above radiance 2, and a radiance of 3
// reads 2 within the dark noise.
TEST(SensorModel, FullWellClipsTheSignal) {
  const SensorParams sensor;
  const LinearImage out = ApplySensorModel(Flat(64, 64, 3.0f, 3.0f, 3.0f), sensor, SensorExposure{});
  const Moments m = MomentsOf(out.rgb);
  for (float v : out.rgb) ASSERT_LE(v, 2.0f);
  EXPECT_NEAR(m.mean, 2.0, 0.01);
}

// The fixed pattern belongs to the camera: with a strong PRNU and little
// temporal noise, two frames of one camera correlate almost perfectly, the
// two cameras' same frame not at all; the same for DSNU in the dark.
TEST(SensorModel, FixedPatternIsTheSameInEveryFrameAndDiffersBetweenCameras) {
  SensorParams prnu;
  prnu.exposure_e = 1e6;
  prnu.full_well_e = 1e7;
  prnu.read_noise_e = 0.0;
  prnu.dsnu_e = 0.0;
  prnu.prnu = 0.2;
  prnu.adc_bits = 16;
  SensorParams dsnu;
  dsnu.prnu = 0.0;
  dsnu.dsnu_e = 40.0;
  dsnu.read_noise_e = 1.0;
  dsnu.black_level_dn = 1000;
  for (const auto& [name, sensor, radiance] : {std::tuple{"prnu", prnu, 0.5f}, std::tuple{"dsnu", dsnu, 0.0f}}) {
    const LinearImage flat = Flat(128, 128, radiance, radiance, radiance);
    const LinearImage left0 = ApplySensorModel(flat, sensor, SensorExposure{0, 0, 0});
    const LinearImage left9 = ApplySensorModel(flat, sensor, SensorExposure{0, 9, 0});
    const LinearImage calib = ApplySensorModel(flat, sensor, SensorExposure{1, 0, 0});
    const LinearImage right0 = ApplySensorModel(flat, sensor, SensorExposure{0, 0, 1});
    const double same_camera = Correlation(left0.rgb, left9.rgb);
    const double calibration = Correlation(left0.rgb, calib.rgb);
    const double other_camera = Correlation(left0.rgb, right0.rgb);
    std::printf("%s: correlation frame 0 / frame 9 %.4f, frame 0 / calib pair 0 %.4f, left / right %.4f\n", name,
                same_camera, calibration, other_camera);
    EXPECT_GT(same_camera, 0.99) << name;
    EXPECT_GT(calibration, 0.99) << name;
    EXPECT_LT(std::abs(other_camera), 0.02) << name;
    EXPECT_NE(left0.rgb, left9.rgb) << name;  // the temporal noise differs
  }
}

TEST(SensorModel, SameSeedGivesTheSameValuesAnotherSeedOrExposureOthers) {
  LinearImage image = Flat(96, 64, 0.2f, 0.4f, 0.6f);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] *= 0.5f + 0.5f * static_cast<float>(i % 7) / 7.0f;
  SensorParams sensor;
  sensor.exposure_e = 800.0;
  sensor.blur_sigma_px = 0.7;
  for (BayerPattern bayer : {BayerPattern::kNone, BayerPattern::kRggb}) {
    sensor.bayer = bayer;
    const SensorExposure exposure{0, 42, 1};
    const LinearImage a = ApplySensorModel(image, sensor, exposure);
    EXPECT_EQ(a.rgb, ApplySensorModel(image, sensor, exposure).rgb);
    SensorParams other_seed = sensor;
    other_seed.seed = 2;
    for (const LinearImage& b :
         {ApplySensorModel(image, other_seed, exposure), ApplySensorModel(image, sensor, SensorExposure{0, 43, 1}),
          ApplySensorModel(image, sensor, SensorExposure{1, 42, 1})}) {
      size_t differ = 0;
      for (size_t i = 0; i < a.rgb.size(); ++i) differ += a.rgb[i] != b.rgb[i];
      EXPECT_GT(differ, a.rgb.size() * 9 / 10);
    }
  }
}

// One SensorModel for a whole render keeps each camera's fixed pattern: its
// images are those of a fresh model per image, whatever the order of cameras,
// exposures and image sizes, and from two threads at once.
TEST(SensorModel, KeptFixedPatternGivesTheValuesOfAFreshModel) {
  LinearImage image = Flat(96, 64, 0.2f, 0.4f, 0.6f);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] *= 0.5f + 0.5f * static_cast<float>(i % 7) / 7.0f;
  const LinearImage small = Flat(32, 16, 0.3f, 0.3f, 0.3f);
  SensorParams sensor;
  sensor.exposure_e = 800.0;
  sensor.prnu = 0.02;
  sensor.dsnu_e = 3.0;
  for (BayerPattern bayer : {BayerPattern::kNone, BayerPattern::kRggb}) {
    sensor.bayer = bayer;
    const SensorModel model(sensor);
    const std::vector<SensorExposure> exposures = {{0, 5, 1}, {0, 5, 0}, {1, 2, 1}, {0, 6, 0}};
    for (const SensorExposure& e : exposures) {
      EXPECT_EQ(model.Apply(image, e).rgb, ApplySensorModel(image, sensor, e).rgb) << e.index << " " << e.camera;
      EXPECT_EQ(model.Apply(small, e).rgb, ApplySensorModel(small, sensor, e).rgb) << e.index << " " << e.camera;
    }
    const SensorModel shared(sensor);
    std::vector<float> right;
    std::thread other([&] { right = shared.Apply(image, SensorExposure{0, 9, 1}).rgb; });
    const std::vector<float> left = shared.Apply(image, SensorExposure{0, 9, 0}).rgb;
    other.join();
    EXPECT_EQ(left, ApplySensorModel(image, sensor, SensorExposure{0, 9, 0}).rgb);
    EXPECT_EQ(right, ApplySensorModel(image, sensor, SensorExposure{0, 9, 1}).rgb);
  }
}

// A grey (and a coloured) flat field goes through the RGGB mosaic and the
// bilinear demosaicing unchanged, to the bit; the pattern is RGGB.
TEST(Bayer, FlatFieldsDemosaicToThemselves) {
  EXPECT_EQ(RggbChannel(0, 0), 0);
  EXPECT_EQ(RggbChannel(0, 1), 1);
  EXPECT_EQ(RggbChannel(1, 0), 1);
  EXPECT_EQ(RggbChannel(1, 1), 2);
  EXPECT_EQ(RggbChannel(6, 8), 0);
  const int width = 9, height = 7;  // odd sizes: the mirrored border keeps the phase
  for (const std::array<float, 3>& colour : {std::array{0.37f, 0.37f, 0.37f}, std::array{0.2f, 0.55f, 0.9f}}) {
    std::vector<float> mosaic(width * height);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) mosaic[y * width + x] = colour[RggbChannel(y, x)];
    }
    const LinearImage out = DemosaicRggbBilinear(mosaic, width, height);
    for (size_t i = 0; i < out.rgb.size(); ++i) ASSERT_EQ(out.rgb[i], colour[i % 3]) << "sample " << i;
  }
}

// Through the whole model: a flat colour under the mosaic keeps each
// channel's mean (the demosaicing averages noisy neighbours, so only the mean
// is compared, within 0.5 %).
TEST(Bayer, SensorWithMosaicKeepsTheChannelMeans) {
  SensorParams sensor;
  sensor.bayer = BayerPattern::kRggb;
  const std::array<float, 3> colour = {0.25f, 0.5f, 0.75f};
  const LinearImage out = ApplySensorModel(Flat(200, 160, colour[0], colour[1], colour[2]), sensor, SensorExposure{});
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (size_t i = c; i < out.rgb.size(); i += 3) sum += out.rgb[i];
    EXPECT_NEAR(sum / (out.rgb.size() / 3), colour[c], 0.005 * colour[c]) << "channel " << c;
  }
}

// The blur keeps the mean of an image whose border band is uniform, keeps a
// flat image exactly, and spreads a point into a Gaussian of the given sigma
// (its second moment sigma^2 within 5 %: the 3-sigma cut takes 2.7 %).
TEST(OpticalBlur, PreservesTheMeanAndSpreadsAPointBySigma) {
  const double sigma = 1.5;
  const int radius = GaussianKernelRadius(sigma);
  EXPECT_EQ(radius, 5);
  LinearImage image = Flat(80, 60, 0.3f, 0.3f, 0.3f);
  std::mt19937 random(5);
  std::uniform_real_distribution<float> value(0.0f, 1.0f);
  for (int y = radius; y < image.height - radius; ++y) {
    for (int x = radius; x < image.width - radius; ++x) {
      for (int c = 0; c < 3; ++c) image.rgb[3 * (y * image.width + x) + c] = value(random);
    }
  }
  const LinearImage blurred = GaussianBlur(image, sigma);
  EXPECT_NEAR(MomentsOf(blurred.rgb).mean, MomentsOf(image.rgb).mean, 1e-5);
  EXPECT_LT(MomentsOf(blurred.rgb).variance, 0.5 * MomentsOf(image.rgb).variance);  // it does blur
  const LinearImage flat = Flat(20, 10, 0.7f, 0.7f, 0.7f);
  EXPECT_EQ(GaussianBlur(flat, sigma).rgb, flat.rgb);
  EXPECT_EQ(GaussianBlur(image, 0.0).rgb, image.rgb);

  LinearImage point = Flat(41, 41, 0.0f, 0.0f, 0.0f);
  point.rgb[3 * (20 * 41 + 20) + 1] = 1.0f;
  const LinearImage spread = GaussianBlur(point, sigma);
  double sum = 0.0, second_moment_x = 0.0;
  for (int y = 0; y < 41; ++y) {
    for (int x = 0; x < 41; ++x) {
      const double v = spread.rgb[3 * (y * 41 + x) + 1];
      sum += v;
      second_moment_x += v * (x - 20) * (x - 20);
    }
  }
  EXPECT_NEAR(sum, 1.0, 1e-6);
  EXPECT_NEAR(second_moment_x / sum / (sigma * sigma), 1.0, 0.05);
}

}  // namespace
}  // namespace aar
