#include "boom_schedule.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "aar/boom.h"
#include "receiver_box.h"

namespace aar::flightpaths {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

// 0 at s <= 0, 1 at s >= 1, 3 s^2 - 2 s^3 between.
double SmoothStep(double s) {
  const double t = std::clamp(s, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

BoomPose Blend(const BoomPose& a, const BoomPose& b, double w) {
  return {a.pitch_deg + w * (b.pitch_deg - a.pitch_deg), a.roll_deg + w * (b.roll_deg - a.roll_deg),
          a.extension_m + w * (b.extension_m - a.extension_m)};
}

}  // namespace

BoomPose BoomPointedAt(const Eigen::Vector3d& target_in_tanker) {
  // The boom's axis is Rx(roll) Ry(-pitch) (-1, 0, 0) = (-cos p, sin r sin p, -cos r sin p) (boom.h).
  const Eigen::Vector3d d = target_in_tanker - kBoomHingeInTanker;
  const Eigen::Vector3d u = d.normalized();
  BoomPose pose;
  pose.pitch_deg = std::clamp(std::acos(std::clamp(-u.x(), -1.0, 1.0)) * kRadToDeg, 0.0, 45.0);
  pose.roll_deg = std::clamp(std::atan2(u.y(), -u.z()) * kRadToDeg, -25.0, 25.0);
  pose.extension_m = std::clamp(d.norm() - kBoomNozzleTipM, 0.0, kBoomTelescopeM);
  return pose;
}

std::vector<FlightSample> AddBoomSchedule(const StereoRig& rig, std::vector<FlightSample> samples,
                                          const BoomScheduleOptions& o) {
  const BoomPose stowed;
  const BoomPose trail{o.trail_pitch_deg, 0.0, o.trail_extension_m};
  for (FlightSample& s : samples) {
    const double range = RangeFromLeftCamera(rig, s.tanker_from_receiver);
    const Eigen::Vector3d receptacle = IsometryFromPose(s.tanker_from_receiver) * o.receptacle_in_receiver;
    if (range >= o.trail_range_m) {
      s.boom =
          Blend(stowed, trail, SmoothStep((o.lower_start_range_m - range) / (o.lower_start_range_m - o.trail_range_m)));
    } else {
      s.boom = Blend(trail, BoomPointedAt(receptacle),
                     SmoothStep((o.trail_range_m - range) / (o.trail_range_m - o.track_range_m)));
    }
    s = RoundToCsvPrecision(s);
  }
  return samples;
}

}  // namespace aar::flightpaths
