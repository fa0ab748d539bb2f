// The temporal filter (pose_filter.h) on synthetic 125 Hz trajectories with known noise: exact on constant-velocity
// motion, no lag on a manoeuvring one, less jitter and error under noise, and windows that restart where they must.

#include "aar/analyzer/pose_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "aar/random_stream.h"

namespace aar {
namespace {

constexpr double kFrameS = 0.008;  // 125 Hz
constexpr size_t kFrames = 1000;

std::array<double, 6> Values(const Pose& p) {
  return {p.translation_m.x(), p.translation_m.y(), p.translation_m.z(), p.roll_deg, p.pitch_deg, p.yaw_deg};
}

double Difference(const std::array<double, 6>& a, const std::array<double, 6>& b, size_t d) {
  const double diff = a[d] - b[d];
  return d < 3 ? diff : WrapDegrees(diff);
}

// A manoeuvring receiver: closing, weaving and rolling, its yaw crossing +-180 deg.
Pose Manoeuvre(double t) {
  const double two_pi = 2.0 * std::numbers::pi;
  Pose p;
  p.translation_m = Eigen::Vector3d(-35.0 + 0.4 * t + 0.3 * std::sin(two_pi * t / 4.0),
                                    0.1 * std::sin(two_pi * t / 3.0), -18.0 + 0.2 * t);
  p.roll_deg = 2.0 * std::sin(two_pi * t / 5.0);
  p.pitch_deg = 1.0 + 1.5 * std::sin(two_pi * t / 2.5 + 1.0);
  p.yaw_deg = WrapDegrees(179.5 + 0.8 * t);
  return p;
}

std::vector<TimedPose> Sequence(double position_noise_m, double angle_noise_deg, uint64_t seed) {
  RandomStream random(seed);
  std::vector<TimedPose> frames;
  for (size_t i = 0; i < kFrames; ++i) {
    const double t = kFrameS * static_cast<double>(i);
    Pose p = Manoeuvre(t);
    for (int d = 0; d < 3; ++d) p.translation_m[d] += position_noise_m * random.Normal();
    p.roll_deg += angle_noise_deg * random.Normal();
    p.pitch_deg += angle_noise_deg * random.Normal();
    p.yaw_deg = WrapDegrees(p.yaw_deg + angle_noise_deg * random.Normal());
    frames.push_back({t, p});
  }
  return frames;
}

// Lag in frames of `poses` behind the truth, per degree of freedom: the time shift that best explains their error as
// the truth's motion, sum(error * velocity) / sum(velocity^2) with the velocity per frame, negated.
std::array<double, 6> LagFrames(const std::vector<std::array<double, 6>>& poses) {
  std::array<double, 6> lag{};
  for (size_t d = 0; d < 6; ++d) {
    double error_velocity = 0.0, velocity_squared = 0.0;
    for (size_t i = 1; i < poses.size(); ++i) {
      const double t = kFrameS * static_cast<double>(i);
      const std::array<double, 6> truth = Values(Manoeuvre(t));
      const double velocity = Difference(truth, Values(Manoeuvre(t - kFrameS)), d);
      error_velocity += Difference(poses[i], truth, d) * velocity;
      velocity_squared += velocity * velocity;
    }
    lag[d] = -error_velocity / velocity_squared;
  }
  return lag;
}

std::vector<std::array<double, 6>> ValuesOf(const std::vector<std::optional<Pose>>& poses) {
  std::vector<std::array<double, 6>> values;
  for (const std::optional<Pose>& p : poses) values.push_back(Values(p.value()));
  return values;
}

TEST(PoseFilter, ExactOnConstantVelocity) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  std::vector<TimedPose> frames;
  for (size_t i = 0; i < 60; ++i) {
    const double t = kFrameS * static_cast<double>(i);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(-40.0 + 1.5 * t, 0.2 - 0.3 * t, -20.0 + 0.1 * t);
    pose.linear() = RotationFromRollPitchYaw(1.0, -2.0, 3.0) * Eigen::AngleAxisd(0.2 * t, axis).toRotationMatrix();
    frames.push_back({t, PoseFromIsometry(pose)});
  }
  const std::vector<std::optional<Pose>> filtered = FilterPoses(frames, PoseFilterOptions{});
  for (size_t i = 0; i < frames.size(); ++i) {
    const std::array<double, 6> a = Values(filtered[i].value());
    const std::array<double, 6> b = Values(*frames[i].pose);
    for (size_t d = 0; d < 6; ++d) EXPECT_NEAR(Difference(a, b, d), 0.0, 1e-9) << "frame " << i << " dof " << d;
  }
}

// Noise-free manoeuvre: the filter follows it within its bias a W^2 / 12 and does not lag, where the causal mean of
// the same 13 frames lags by 6.
TEST(PoseFilter, DoesNotLagAManoeuvre) {
  const std::vector<TimedPose> frames = Sequence(0.0, 0.0, 1);
  const std::vector<std::array<double, 6>> filtered = ValuesOf(FilterPoses(frames, PoseFilterOptions{}));
  for (size_t i = 0; i < frames.size(); ++i) {
    const std::array<double, 6> truth = Values(*frames[i].pose);
    for (size_t d = 0; d < 3; ++d) EXPECT_NEAR(filtered[i][d], truth[d], 1e-3) << "frame " << i;
    for (size_t d = 3; d < 6; ++d) EXPECT_NEAR(Difference(filtered[i], truth, d), 0.0, 0.01) << "frame " << i;
  }
  const std::array<double, 6> lag = LagFrames(filtered);
  for (size_t d = 0; d < 6; ++d) EXPECT_LT(std::abs(lag[d]), 0.05) << "dof " << d;

  std::vector<std::array<double, 6>> mean(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    const size_t first = i >= 12 ? i - 12 : 0;
    for (size_t j = first; j <= i; ++j) {
      for (size_t d = 0; d < 5; ++d) mean[i][d] += Values(*frames[j].pose)[d] / static_cast<double>(i + 1 - first);
    }
  }
  EXPECT_NEAR(LagFrames(mean)[0], 6.0, 0.5);  // the lag measure itself works
}

// 1 cm and 0.1 deg of white noise: the filter cuts the jitter (the RMS change of the error from frame to frame) to
// under a third and the RMS error to under two thirds, still without a lag.
TEST(PoseFilter, CutsJitterAndErrorUnderNoise) {
  const std::vector<TimedPose> frames = Sequence(0.01, 0.1, 7);
  const std::vector<std::array<double, 6>> filtered = ValuesOf(FilterPoses(frames, PoseFilterOptions{}));
  std::vector<std::array<double, 6>> raw;
  for (const TimedPose& f : frames) raw.push_back(Values(*f.pose));
  const auto rms = [&](const std::vector<std::array<double, 6>>& poses, size_t d, bool jitter) {
    double sum = 0.0;
    size_t n = 0;
    for (size_t i = 20; i < poses.size(); ++i) {  // after the first full window
      const double t = kFrameS * static_cast<double>(i);
      const double error = Difference(poses[i], Values(Manoeuvre(t)), d);
      const double previous = Difference(poses[i - 1], Values(Manoeuvre(t - kFrameS)), d);
      const double value = jitter ? error - previous : error;
      sum += value * value;
      ++n;
    }
    return std::sqrt(sum / static_cast<double>(n));
  };
  const std::array<double, 6> lag = LagFrames(filtered);
  for (size_t d = 0; d < 6; ++d) {
    EXPECT_LT(rms(filtered, d, true), rms(raw, d, true) / 3.0) << "dof " << d;
    EXPECT_LT(rms(filtered, d, false), rms(raw, d, false) * 2.0 / 3.0) << "dof " << d;
    if (d != 1) {  // y barely moves: its lag is ill-defined
      EXPECT_LT(std::abs(lag[d]), 1.0) << "dof " << d;
    }
  }
}

TEST(PoseFilter, WindowsRestartAfterAGapAndWhereTimeDoesNotIncrease) {
  std::vector<TimedPose> frames = Sequence(0.01, 0.1, 3);
  frames.resize(40);
  frames[20].pose.reset();
  frames[30].time_s = frames[29].time_s;  // a repeated time stamp
  const std::vector<std::optional<Pose>> filtered = FilterPoses(frames, PoseFilterOptions{});
  EXPECT_FALSE(filtered[20]);
  for (size_t i : {0u, 1u, 21u, 22u, 30u, 31u}) {  // fewer than three estimates in the window: the estimate itself
    ASSERT_TRUE(filtered[i]);
    EXPECT_EQ(filtered[i]->translation_m, frames[i].pose->translation_m) << "frame " << i;
    EXPECT_EQ(filtered[i]->roll_deg, frames[i].pose->roll_deg) << "frame " << i;
  }
  for (size_t i : {2u, 19u, 23u, 29u, 32u}) {
    ASSERT_TRUE(filtered[i]);
    EXPECT_NE(filtered[i]->translation_m, frames[i].pose->translation_m) << "frame " << i;
  }
  // Windows shorter than two frame intervals leave every estimate as it is.
  const std::vector<std::optional<Pose>> narrow = FilterPoses(frames, PoseFilterOptions{.window_s = 1.9 * kFrameS});
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(narrow[i].has_value(), frames[i].pose.has_value());
    if (narrow[i]) {
      EXPECT_EQ(narrow[i]->yaw_deg, frames[i].pose->yaw_deg);
    }
  }
}

}  // namespace
}  // namespace aar
